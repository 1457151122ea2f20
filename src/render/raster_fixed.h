// The fixed-point raster core: the same contract as RasterizeDepthReference (raster.h), with
// vertices snapped to a 1/16-pixel grid (the paper's sub-pixel quantization) so that edge
// functions are exact integers, stepped incrementally across the triangle's bounding box.
//
// Differences from the reference: coverage is decided on the snapped triangle (a pixel centre
// within 1/32 pixel of an edge may flip), and depth comes from the 1/z plane through the
// snapped vertices. Triangles larger than the integer range (a side over 2048 pixels, or a
// vertex more than 16384 pixels off the box) go through the float reference path instead,
// so the result never depends on overflow.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "render/raster.h"

namespace mcpose::render {

inline constexpr int kSubpixelBits = 4;

void RasterizeDepthFixedPoint(std::span<const ScreenVertex> vertices,
                              std::span<const std::array<uint32_t, 3>> triangles,
                              const RasterParams& params, float* zbuf, RasterStats* stats);

}  // namespace mcpose::render

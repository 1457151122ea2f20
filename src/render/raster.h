// Partial rasterization of one pose hypothesis: a depth z-buffer of a mesh, only inside a
// pixel box, with backface culling. This is the scalar reference ("raster core") that every
// faster kernel is tested against.
//
// Conventions: pixel (x, y) is centred on (u, v) = (x, y) (see mcpose/camera.h). A pixel is
// covered when its centre lies inside the triangle, with the top-left rule on shared edges,
// so two triangles sharing an edge never both cover a pixel. Depth is interpolated
// perspective-correctly (1/z is linear in screen space). Triangles are wound
// counter-clockwise seen from outside; front faces have negative signed area in the image.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include <Eigen/Core>

#include "mcpose/counters.h"

namespace mcpose::render {

// Half-open pixel rectangle [x0, x1) x [y0, y1).
struct PixelRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
  int64_t area() const { return int64_t{width()} * height(); }
  bool empty() const { return x1 <= x0 || y1 <= y0; }
};

struct RasterParams {
  float fx = 0, fy = 0, cx = 0, cy = 0;
  PixelRect box;               // render only inside this box
  float z_near_m = 0.05f;      // triangles with a vertex closer than this are culled
  bool cull_backfaces = true;
};

// A vertex after the camera transform: pixel coordinates and camera depth.
struct ScreenVertex {
  float u = 0, v = 0;
  float z = 0;  // camera-frame depth, metres
};

// X_cam = R * X_model + t, then the pinhole projection.
void ProjectVertices(std::span<const Eigen::Vector3f> vertices_m, const Eigen::Matrix3f& R,
                     const Eigen::Vector3f& t, const RasterParams& params,
                     std::span<ScreenVertex> out);

// The pixels of `box` that triangles over these vertices can cover: the vertices' bounding
// box grown by a pixel on each side (so sub-pixel snapping stays inside), clipped to `box`
// (empty if none). The whole box when a
// coordinate is not finite. Every rasterizer here writes only inside this rect.
PixelRect CoverBound(std::span<const ScreenVertex> vertices, const PixelRect& box);
// CoverBound with the bounds {min u, max u, min v, max v} of other, finite vertices folded in
// (CoverBound is CoverBoundFrom with {inf, -inf, inf, -inf}).
PixelRect CoverBoundFrom(std::span<const ScreenVertex> vertices, const PixelRect& box, const float bounds[4]);

// ProjectVertices and CoverBound a SIMD vector of vertices at a time (render/project_simd.cc,
// Highway, runtime-dispatched): bit-identical results (tested on every target).
void ProjectVerticesSimd(std::span<const Eigen::Vector3f> vertices_m, const Eigen::Matrix3f& R,
                         const Eigen::Vector3f& t, const RasterParams& params, std::span<ScreenVertex> out);
PixelRect CoverBoundSimd(std::span<const ScreenVertex> vertices, const PixelRect& box);

// Renders the triangles into `zbuf` (params.box sized, row-major, row stride box.width()),
// keeping the nearest depth. The caller fills zbuf with +infinity first; pixels no triangle
// covers keep it. Adds to *stats.
void RasterizeDepthReference(std::span<const ScreenVertex> vertices,
                             std::span<const std::array<uint32_t, 3>> triangles,
                             const RasterParams& params, float* zbuf, RasterCounters* stats);

// Slack (floats) the SIMD kernels need after the last z-buffer pixel: the widest vector.
inline constexpr size_t kSimdPadFloats = 64;

// RasterizeDepthReference reorganised for SIMD (render/raster_float_simd.cc, Highway,
// runtime-dispatched): a vector of triangles classified at a time, then a vector of pixels of
// a row at a time, with the reference's float operations in the reference's order. The
// z-buffer and the statistics are bit-identical to the reference's (tested on every target).
// zbuf needs kSimdPadFloats of slack after the box (pixels past a row's end are stored back
// unchanged).
void RasterizeDepthFloatSimd(std::span<const ScreenVertex> vertices,
                             std::span<const std::array<uint32_t, 3>> triangles,
                             const RasterParams& params, float* zbuf, RasterCounters* stats);

}  // namespace mcpose::render

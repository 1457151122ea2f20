// Shared pieces of the raster-core tests: the camera and box the unit tests render through,
// and readable gtest output for RasterStats.
#pragma once

#include <ostream>

#include "render/raster.h"

namespace mcpose::render {

// The YCB-Video camera, a 220 x 180 box, back faces culled or not.
inline RasterParams TestRasterParams(bool cull) {
  RasterParams p;
  p.fx = 1066.778f, p.fy = 1067.487f, p.cx = 312.9869f, p.cy = 241.3109f;
  p.box = PixelRect{200, 150, 420, 330};
  p.cull_backfaces = cull;
  return p;
}

// gtest prints RasterStats field by field (EXPECT_EQ on two of them).
inline void PrintTo(const RasterStats& s, std::ostream* os) {
  *os << "{triangles " << s.triangles << ", near " << s.culled_near << ", degenerate " << s.culled_degenerate
      << ", backface " << s.culled_backface << ", outside " << s.culled_outside_box << ", between "
      << s.culled_between_pixels << ", rasterized " << s.rasterized << ", fragments " << s.fragments
      << ", clusters " << s.clusters << " (backface " << s.clusters_culled_backface << ", outside "
      << s.clusters_culled_outside_box << ")}";
}

}  // namespace mcpose::render

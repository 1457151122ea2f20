// Shared pieces of the raster-core tests: the camera and box the unit tests render through,
// and readable gtest output for RasterCounters.
#pragma once

#include <ostream>
#include <utility>

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

}  // namespace mcpose::render

namespace mcpose {

// gtest prints RasterCounters field by field (EXPECT_EQ on two of them).
inline void PrintTo(const RasterCounters& s, std::ostream* os) {
  const char* sep = "{";
#define MCPOSE_PRINT_COUNTER(name, doc) *os << std::exchange(sep, ", ") << #name " " << s.name;
  MCPOSE_RASTER_COUNTERS(MCPOSE_PRINT_COUNTER)
#undef MCPOSE_PRINT_COUNTER
  *os << "}";
}

}  // namespace mcpose

// Images held by value: observed depth in metres (0 = no measurement), 8-bit masks and 8-bit
// colour.
#pragma once

#include <cstdint>
#include <vector>

namespace mcpose {

struct DepthImage {
  int width = 0, height = 0;
  std::vector<float> depth_m;  // row-major, width * height; 0 marks an invalid pixel
  float at(int x, int y) const { return depth_m[static_cast<size_t>(y) * width + x]; }
};

struct MaskImage {
  int width = 0, height = 0;
  std::vector<uint8_t> values;  // row-major, width * height; nonzero = inside
  bool at(int x, int y) const { return values[static_cast<size_t>(y) * width + x] != 0; }
};

// 8-bit RGBA colour, row-major, row 0 at the top. Alpha 0 marks an unknown colour (a texel no
// view has seen); colour frames and opaque textures have alpha 255 everywhere.
struct ColourImage {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;  // 4 * width * height
  const uint8_t* at(int x, int y) const { return rgba.data() + 4 * (static_cast<size_t>(y) * width + x); }
};

}  // namespace mcpose

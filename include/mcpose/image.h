// Images held by value: observed depth in metres (0 = no measurement) and 8-bit masks.
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

}  // namespace mcpose

// Pinhole intrinsics. Pixel centres sit at integer coordinates: pixel (i, j) is centred on
// (u, v) = (i, j), with u = fx * X / Z + cx and v = fy * Y / Z + cy (the YCB-Video convention;
// it reproduces the dataset's label images best).
#pragma once

#include <string>

namespace mcpose {

struct Intrinsics {
  double fx = 0, fy = 0, cx = 0, cy = 0;
  int width = 0, height = 0;

  // True if all values are finite, focal lengths positive and the image non-empty.
  bool IsValid(std::string* error) const;
};

}  // namespace mcpose

// PNG depth images and masks (libpng). Errors name the file and the problem: missing file,
// not a PNG, truncated or corrupt data, wrong bit depth or channel count.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mcpose/image.h"
#include "mcpose/status.h"

namespace mcpose::io {

// A 16-bit single-channel image as stored (raw sensor units).
struct Gray16Image {
  int width = 0, height = 0;
  std::vector<uint16_t> values;  // row-major, width * height
};

// Raw values of a 16-bit single-channel grayscale PNG; any other format is an error.
StatusOr<Gray16Image> ReadGray16Png(const std::string& path);

// Depth in metres: depth_m = float(value * metres_per_unit); 0 and the saturated 65535 both
// mean no measurement and become 0. 65535 * `metres_per_unit` must lie in 1 cm-100 m
// (core/physical_limits.h); `metres_per_unit` is 1 / factor_depth in YCB-Video,
// depth_scale / 1000 in BOP.
StatusOr<DepthImage> ReadDepthPng(const std::string& path, double metres_per_unit);

// A mask or label image: 8-bit (or 1/2/4-bit) grayscale values as stored, so label images keep
// their class indices; a 16-bit image is an error.
StatusOr<MaskImage> ReadMaskPng(const std::string& path);

// An 8-bit colour image: RGB or RGBA (alpha kept), palette or 8-bit grayscale (expanded to
// RGB); alpha is 255 where the file has none. 16-bit samples are an error (bit depth named).
StatusOr<ColourImage> ReadColourPng(const std::string& path);

// Width and height from the header of the PNG at `path`, without decoding it.
struct ImageSize {
  int width = 0, height = 0;
};
StatusOr<ImageSize> ReadPngSize(const std::string& path);

// Every reader refuses, before allocating pixels, a header claiming more than
// limits::kMaxImageSide pixels a side or more pixel bytes than the file could inflate to.

// Writers, atomic (temporary file and rename): 16-bit grayscale, 8-bit grayscale, and 8-bit
// RGBA (or RGB when every alpha is 255).
Status WriteGray16Png(const std::string& path, const Gray16Image& image);
Status WriteMaskPng(const std::string& path, const MaskImage& mask);
Status WriteColourPng(const std::string& path, const ColourImage& image);

}  // namespace mcpose::io

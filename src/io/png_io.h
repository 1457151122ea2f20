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

// Depth in metres: depth_m = float(value * metres_per_unit), 0 stays 0 (no measurement).
// `metres_per_unit` must be finite and positive (1 / factor_depth in YCB-Video,
// depth_scale / 1000 in BOP).
StatusOr<DepthImage> ReadDepthPng(const std::string& path, double metres_per_unit);

// A mask or label image: 8-bit (or 1/2/4-bit) grayscale values as stored, so label images keep
// their class indices; 16-bit grayscale is mapped to 255 where nonzero, 0 elsewhere.
StatusOr<MaskImage> ReadMaskPng(const std::string& path);

// An 8-bit colour image: RGB or RGBA (alpha kept), palette or 8-bit grayscale (expanded to
// RGB); alpha is 255 where the file has none. 16-bit samples are an error (bit depth named).
StatusOr<ColourImage> ReadColourPng(const std::string& path);

// Writers, atomic (temporary file and rename): 16-bit grayscale, 8-bit grayscale, and 8-bit
// RGBA (or RGB when every alpha is 255).
Status WriteGray16Png(const std::string& path, const Gray16Image& image);
Status WriteMaskPng(const std::string& path, const MaskImage& mask);
Status WriteColourPng(const std::string& path, const ColourImage& image);

}  // namespace mcpose::io

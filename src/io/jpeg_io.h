// JPEG colour images (libjpeg-turbo's TurboJPEG API). Errors name the file and the problem.
#pragma once

#include <string>

#include "mcpose/image.h"
#include "mcpose/status.h"

namespace mcpose::io {

// Decodes a JPEG file to RGBA (alpha 255). A truncated or corrupt file is an error, also where
// the decoder could still return part of the image.
StatusOr<ColourImage> ReadJpeg(const std::string& path);

// A colour image in either format, chosen by the file's signature (PNG: ReadColourPng, JPEG:
// ReadJpeg); anything else is an error naming the file.
StatusOr<ColourImage> ReadColourImage(const std::string& path);

}  // namespace mcpose::io

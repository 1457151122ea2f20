// JPEG colour images (libjpeg-turbo's TurboJPEG API). Errors name the file and the problem.
#pragma once

#include <string>
#include <string_view>

#include "mcpose/image.h"
#include "mcpose/status.h"

namespace mcpose::io {

// Decodes a JPEG file to RGBA (alpha 255). A truncated or corrupt file is an error, also where
// the decoder could still return part of the image.
StatusOr<ColourImage> ReadJpeg(const std::string& path);
// The same from JPEG bytes in memory; `path` names them in errors.
StatusOr<ColourImage> DecodeJpeg(std::string_view bytes, const std::string& path);
// `image` as a baseline JPEG of `quality` (1-100), 4:2:0 chroma; alpha is dropped.
StatusOr<std::string> EncodeJpeg(const ColourImage& image, int quality);

// A colour image in either format, chosen by the file's signature (PNG: ReadColourPng, JPEG:
// ReadJpeg); anything else is an error naming the file.
StatusOr<ColourImage> ReadColourImage(const std::string& path);

}  // namespace mcpose::io

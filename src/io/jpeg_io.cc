#include "io/jpeg_io.h"

#include <turbojpeg.h>

#include <cstring>
#include <exception>
#include <fstream>
#include <memory>

#include "mcpose/limits.h"
#include "mcpose/io_util.h"
#include "mcpose/png_io.h"

namespace mcpose::io {

namespace {

struct TjDeleter {
  void operator()(void* handle) const { tjDestroy(handle); }
};

}  // namespace

StatusOr<ColourImage> ReadJpeg(const std::string& path) {
  MCPOSE_ASSIGN_OR_RETURN(std::string bytes, ReadFileToString(path));
  return DecodeJpeg(bytes, path);
}

StatusOr<ColourImage> DecodeJpeg(std::string_view bytes, const std::string& path) {
  std::unique_ptr<void, TjDeleter> tj(tjInitDecompress());
  if (!tj) return Internal(path + ": cannot start the JPEG decoder");
  auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const unsigned long size = static_cast<unsigned long>(bytes.size());
  int width = 0, height = 0, subsampling = 0, colorspace = 0;
  if (tjDecompressHeader3(tj.get(), data, size, &width, &height, &subsampling, &colorspace) != 0)
    return DataLoss(path + ": not a readable JPEG file (" + tjGetErrorStr2(tj.get()) + ")");
  if (width <= 0 || height <= 0) return DataLoss(path + ": JPEG file has an empty image");
  // A JPEG codes at least a few bits per 8 x 8 block: far more pixels than 1,000 per byte is a
  // header that lies. Both checks come before the pixel buffer is allocated.
  constexpr double kMaxPixelsPerByte = 1000.0;
  if (width > limits::kMaxImageSide || height > limits::kMaxImageSide ||
      static_cast<double>(width) * height > kMaxPixelsPerByte * static_cast<double>(size))
    return DataLoss(path + ": JPEG header claims " + std::to_string(width) + "x" + std::to_string(height) +
                    " pixels, more than the limit of " + std::to_string(limits::kMaxImageSide) +
                    " per side or than its " + std::to_string(size) + " bytes can hold");
  ColourImage image;
  image.width = width, image.height = height;
  try {
    image.rgba.resize(4 * static_cast<size_t>(width) * height);
  } catch (const std::exception&) {
    return DataLoss(path + ": image too large to decode (" + std::to_string(width) + "x" + std::to_string(height) + ")");
  }
  // Any warning (a premature end of data, corrupt entropy data) is an error: the pixels would be
  // partly made up.
  if (tjDecompress2(tj.get(), data, size, image.rgba.data(), width, 0, height, TJPF_RGBA, TJFLAG_STOPONWARNING) != 0) {
    const std::string what = tjGetErrorStr2(tj.get());
    if (what.find("end of") != std::string::npos || what.find("Premature") != std::string::npos)
      return DataLoss(path + ": JPEG file is truncated (" + what + ")");
    return DataLoss(path + ": corrupt JPEG data (" + what + ")");
  }
  return image;
}

StatusOr<std::string> EncodeJpeg(const ColourImage& image, int quality) {
  if (quality < 1 || quality > 100) return InvalidArgument("JPEG quality " + std::to_string(quality) + " is not in 1..100");
  if (image.width <= 0 || image.height <= 0 || image.rgba.size() != 4 * static_cast<size_t>(image.width) * image.height)
    return InvalidArgument("cannot encode an empty or inconsistent image as JPEG");
  std::unique_ptr<void, TjDeleter> tj(tjInitCompress());
  if (!tj) return Internal("cannot start the JPEG encoder");
  unsigned char* out = nullptr;
  unsigned long size = 0;
  // 4:2:0 chroma subsampling, as cameras and most encoders write.
  if (tjCompress2(tj.get(), image.rgba.data(), image.width, 0, image.height, TJPF_RGBA, &out, &size, TJSAMP_420,
                  quality, 0) != 0) {
    const std::string what = tjGetErrorStr2(tj.get());
    tjFree(out);
    return Internal("JPEG encoding failed (" + what + ")");
  }
  std::string bytes(reinterpret_cast<const char*>(out), size);
  tjFree(out);
  return bytes;
}

StatusOr<ColourImage> ReadColourImage(const std::string& path) {
  unsigned char head[8] = {0};
  std::ifstream in(path, std::ios::binary);
  if (!in) return NotFound(path + ": file does not exist or cannot be read");
  in.read(reinterpret_cast<char*>(head), sizeof head);
  const std::streamsize got = in.gcount();
  static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (got == 8 && std::memcmp(head, kPng, 8) == 0) return ReadColourPng(path);
  if (got >= 3 && head[0] == 0xFF && head[1] == 0xD8 && head[2] == 0xFF) return ReadJpeg(path);
  return DataLoss(path + ": not a PNG or JPEG file");
}

}  // namespace mcpose::io

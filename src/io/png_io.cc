#include "mcpose/png_io.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <new>
#include <string_view>

#include "mcpose/limits.h"
#include "mcpose/io_util.h"

namespace mcpose::io {
namespace {

constexpr size_t kPngSignatureBytes = 8;

// State shared with the libpng callbacks. It lives in the caller's frame, outside the function
// that calls setjmp, so nothing it holds is left indeterminate by a longjmp.
struct PngReadState {
  const std::string* bytes = nullptr;
  size_t offset = 0;
  std::string error;  // set by the error callback before it jumps back
  bool truncated = false;

  // Header of the image.
  png_uint_32 width = 0, height = 0;
  int bit_depth = 0, color_type = 0, interlace = 0;

  // Decoded rows after the transforms we ask for.
  std::vector<unsigned char> pixels;
  std::vector<png_bytep> rows;  // pointers into `pixels`
  size_t row_bytes = 0;
};

// Sizes the pixel buffer and the row pointers; false if the memory cannot be had.
bool AllocatePixels(PngReadState* state) {
  try {
    state->pixels.resize(state->row_bytes * state->height);
    state->rows.resize(state->height);
  } catch (const std::exception&) {
    return false;
  }
  for (png_uint_32 y = 0; y < state->height; ++y) {
    state->rows[y] = state->pixels.data() + y * state->row_bytes;
  }
  return true;
}

void ReadFromMemory(png_structp png, png_bytep out, png_size_t length) {
  auto* state = static_cast<PngReadState*>(png_get_io_ptr(png));
  if (state->offset + length > state->bytes->size()) {
    state->truncated = true;
    png_error(png, "unexpected end of file");
  }
  std::memcpy(out, state->bytes->data() + state->offset, length);
  state->offset += length;
}

void OnPngError(png_structp png, png_const_charp message) {
  auto* state = static_cast<PngReadState*>(png_get_error_ptr(png));
  if (state->error.empty()) state->error = message ? message : "unknown libpng error";
  png_longjmp(png, 1);
}

void OnPngWarning(png_structp, png_const_charp) {}  // benign (e.g. unknown chunks): ignored

// Reading, libpng reports damage it finds once every row is decoded (a zlib checksum that fails
// after the last row, compressed data past the image) as a warning on the IDAT chunk: the pixels
// may be wrong, so that is an error. Other warnings (unknown or ancillary chunks) are ignored.
void OnPngReadWarning(png_structp png, png_const_charp message) {
  const std::string_view m = message ? message : "";
  for (std::string_view damage : {"IDAT", "data check", "compressed data", "image data", "CRC"})
    if (m.find(damage) != std::string_view::npos) OnPngError(png, message);
}

const char* ColorTypeName(int color_type) {
  switch (color_type) {
    case PNG_COLOR_TYPE_GRAY: return "grayscale";
    case PNG_COLOR_TYPE_GRAY_ALPHA: return "grayscale+alpha";
    case PNG_COLOR_TYPE_PALETTE: return "palette";
    case PNG_COLOR_TYPE_RGB: return "RGB";
    case PNG_COLOR_TYPE_RGB_ALPHA: return "RGBA";
  }
  return "unknown color type";
}

int Channels(int color_type) {
  switch (color_type) {
    case PNG_COLOR_TYPE_GRAY_ALPHA: return 2;
    case PNG_COLOR_TYPE_RGB: return 3;
    case PNG_COLOR_TYPE_RGB_ALPHA: return 4;
  }
  return 1;
}

std::string Describe(const PngReadState& s) {
  return std::to_string(s.bit_depth) + "-bit " + ColorTypeName(s.color_type) + " (" +
         std::to_string(Channels(s.color_type)) + " channel" +
         (Channels(s.color_type) > 1 ? "s" : "") + ")";
}

// What the caller accepts; checked between reading the header and decoding the pixels.
enum class PngKind { kGray16, kMask, kColour };

bool Accepts(PngKind kind, const PngReadState& s) {
  if (kind == PngKind::kColour) return s.bit_depth <= 8;  // any colour type, 8-bit or less
  if (s.color_type != PNG_COLOR_TYPE_GRAY) return false;
  if (kind == PngKind::kGray16) return s.bit_depth == 16;
  return s.bit_depth <= 8;  // masks: gray of 1, 2, 4 or 8 bits (a 16-bit one is not a label image)
}

// zlib's deflate shrinks data at most about 1032:1; a header claiming more pixel bytes than the
// file could inflate to is refused before any pixel buffer is allocated.
constexpr double kMaxDeflateRatio = 1032.0;

// The raw bytes an image of this header decodes to, before our transforms.
double RawImageBytes(const PngReadState& s) {
  const double bits_per_pixel = static_cast<double>(s.bit_depth) * Channels(s.color_type);
  return std::ceil(static_cast<double>(s.width) * bits_per_pixel / 8.0) * s.height;
}

// The libpng calls. Returns 0 on success, 1 after a libpng error, 2 if the format is refused,
// 3 if the pixels do not fit in memory, 4 if the header claims a size beyond kMaxImageSide or
// beyond what the file's bytes can hold. Everything that outlives a longjmp lives in `state`
// (the caller's frame), so no destructor is skipped and no local is left indeterminate.
int DecodePng(PngReadState* state, PngKind kind) {
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, state, OnPngError, OnPngReadWarning);
  if (!png) return 1;
  png_infop info = png_create_info_struct(png);
  if (!info) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    return 1;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    return 1;
  }
  png_set_read_fn(png, state, ReadFromMemory);
  png_set_user_limits(png, limits::kMaxImageSide, limits::kMaxImageSide);
  png_read_info(png, info);
  png_get_IHDR(png, info, &state->width, &state->height, &state->bit_depth, &state->color_type,
               &state->interlace, nullptr, nullptr);
  if (state->width > static_cast<png_uint_32>(limits::kMaxImageSide) ||
      state->height > static_cast<png_uint_32>(limits::kMaxImageSide) ||
      RawImageBytes(*state) > kMaxDeflateRatio * static_cast<double>(state->bytes->size())) {
    png_destroy_read_struct(&png, &info, nullptr);
    return 4;
  }
  if (!Accepts(kind, *state)) {
    png_destroy_read_struct(&png, &info, nullptr);
    return 2;
  }
  // Sub-byte gray masks become one byte per pixel; 16-bit stays big-endian (decoded below).
  // Colour: everything becomes 8-bit RGBA (palette and gray expanded, opaque alpha added).
  if (kind == PngKind::kColour) {
    if (state->color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
    if (png_get_valid(png, info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(png);
    if (state->color_type == PNG_COLOR_TYPE_GRAY || state->color_type == PNG_COLOR_TYPE_GRAY_ALPHA)
      png_set_gray_to_rgb(png);
    if (state->bit_depth < 8) png_set_expand(png);
    png_set_filler(png, 0xff, PNG_FILLER_AFTER);
  } else if (state->bit_depth < 8) {
    png_set_expand_gray_1_2_4_to_8(png);
  }
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  state->row_bytes = png_get_rowbytes(png, info);
  if (!AllocatePixels(state)) {
    png_destroy_read_struct(&png, &info, nullptr);
    return 3;
  }
  png_read_image(png, state->rows.data());
  png_read_end(png, nullptr);  // checks the chunks after the image data (truncation, CRC)
  png_destroy_read_struct(&png, &info, nullptr);
  return 0;
}

// Reads the file, checks the signature and decodes. Errors name `path`.
Status ReadPng(const std::string& path, PngKind kind, const char* wanted, PngReadState* state) {
  StatusOr<std::string> bytes = ReadFileToString(path);
  if (!bytes.ok()) return bytes.status();
  if (bytes->size() < kPngSignatureBytes ||
      png_sig_cmp(reinterpret_cast<png_const_bytep>(bytes->data()), 0, kPngSignatureBytes) != 0) {
    return DataLoss(path + ": not a PNG file (bad signature, " + std::to_string(bytes->size()) +
                    " bytes)");
  }
  state->bytes = &*bytes;
  const int result = DecodePng(state, kind);
  state->bytes = nullptr;
  if (result == 4) {
    return DataLoss(path + ": PNG header claims " + std::to_string(state->width) + "x" +
                    std::to_string(state->height) + " pixels, more than the limit of " +
                    std::to_string(limits::kMaxImageSide) + " per side or than its " +
                    std::to_string(bytes->size()) + " bytes can hold");
  }
  if (result == 3) {
    return DataLoss(path + ": image too large to decode (" + std::to_string(state->width) + "x" +
                    std::to_string(state->height) + ")");
  }
  if (result == 2) {
    return InvalidArgument(path + ": " + wanted + ", got " + Describe(*state) + " " +
                           std::to_string(state->width) + "x" + std::to_string(state->height));
  }
  if (result != 0) {
    if (state->error.find("exceeds user limit") != std::string::npos)
      return DataLoss(path + ": PNG header claims more than " + std::to_string(limits::kMaxImageSide) +
                      " pixels per side (libpng: " + state->error + ")");
    if (state->truncated) return DataLoss(path + ": PNG file is truncated (unexpected end of file)");
    return DataLoss(path + ": corrupt PNG data (libpng: " +
                    (state->error.empty() ? std::string("out of memory") : state->error) + ")");
  }
  return Status::Ok();
}

// Shared PNG encoder into `out`: 8- or 16-bit grayscale from big-endian row bytes, or 8-bit RGB / RGBA.
int EncodePng(std::string* out, int width, int height, int bit_depth, int color_type,
              const std::vector<unsigned char>& bytes, std::string* error) {
  png_structp png =
      png_create_write_struct(PNG_LIBPNG_VER_STRING, error,
                              [](png_structp p, png_const_charp m) {
                                *static_cast<std::string*>(png_get_error_ptr(p)) = m;
                                png_longjmp(p, 1);
                              },
                              OnPngWarning);
  if (!png) return 1;
  png_infop info = png_create_info_struct(png);
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    return 1;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return 1;
  }
  png_set_write_fn(
      png, out,
      [](png_structp p, png_bytep data, png_size_t length) {
        try {
          static_cast<std::string*>(png_get_io_ptr(p))->append(reinterpret_cast<const char*>(data), length);
        } catch (const std::bad_alloc&) {
          png_error(p, "out of memory");  // no C++ exception through libpng's frames
        }
      },
      nullptr);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height),
               bit_depth, color_type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  const size_t row_bytes = static_cast<size_t>(width) * (bit_depth / 8) * Channels(color_type);
  for (int y = 0; y < height; ++y) {
    png_write_row(png, const_cast<png_bytep>(bytes.data() + y * row_bytes));
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return 0;
}

Status WritePng(const std::string& path, int width, int height, int bit_depth, int color_type,
                const std::vector<unsigned char>& bytes) {
  if (width <= 0 || height <= 0) {
    return InvalidArgument(path + ": cannot write an empty image (" + std::to_string(width) + "x" +
                           std::to_string(height) + ")");
  }
  std::string encoded, error;
  if (EncodePng(&encoded, width, height, bit_depth, color_type, bytes, &error) != 0)
    return Internal(path + ": PNG encoding failed (" + (error.empty() ? "out of memory" : error) + ")");
  return io::WriteFileAtomic(path, encoded);
}

}  // namespace

StatusOr<Gray16Image> ReadGray16Png(const std::string& path) {
  PngReadState state;
  MCPOSE_RETURN_IF_ERROR(
      ReadPng(path, PngKind::kGray16, "depth PNG must be 16-bit single-channel", &state));
  Gray16Image image;
  image.width = static_cast<int>(state.width);
  image.height = static_cast<int>(state.height);
  image.values.resize(static_cast<size_t>(image.width) * image.height);
  // PNG stores 16-bit samples big-endian.
  for (size_t i = 0; i < image.values.size(); ++i) {
    image.values[i] = static_cast<uint16_t>((state.pixels[2 * i] << 8) | state.pixels[2 * i + 1]);
  }
  return image;
}

StatusOr<DepthImage> ReadDepthPng(const std::string& path, double metres_per_unit) {
  if (const std::string problem = limits::CheckDepthScale(metres_per_unit); !problem.empty()) {
    return InvalidArgument(path + ": " + problem);
  }
  MCPOSE_ASSIGN_OR_RETURN(Gray16Image raw, ReadGray16Png(path));
  DepthImage depth;
  depth.width = raw.width;
  depth.height = raw.height;
  depth.depth_m.resize(raw.values.size());
  for (size_t i = 0; i < raw.values.size(); ++i) {
    // The saturated value is a sensor's "out of range", no measurement, as 0 is.
    const uint16_t v = raw.values[i] == limits::kSaturatedDepth ? 0 : raw.values[i];
    depth.depth_m[i] = static_cast<float>(v * metres_per_unit);
  }
  return depth;
}

StatusOr<MaskImage> ReadMaskPng(const std::string& path) {
  PngReadState state;
  MCPOSE_RETURN_IF_ERROR(
      ReadPng(path, PngKind::kMask, "mask PNG must be single-channel grayscale of at most 8 bits", &state));
  MaskImage mask;
  mask.width = static_cast<int>(state.width);
  mask.height = static_cast<int>(state.height);
  const size_t n = static_cast<size_t>(mask.width) * mask.height;
  mask.values.resize(n);
  std::memcpy(mask.values.data(), state.pixels.data(), n);
  return mask;
}

Status WriteGray16Png(const std::string& path, const Gray16Image& image) {
  const size_t n = static_cast<size_t>(std::max(image.width, 0)) * std::max(image.height, 0);
  if (image.values.size() != n) {
    return InvalidArgument(path + ": image has " + std::to_string(image.values.size()) +
                           " values, expected " + std::to_string(n));
  }
  std::vector<unsigned char> bytes(2 * n);
  for (size_t i = 0; i < n; ++i) {
    bytes[2 * i] = static_cast<unsigned char>(image.values[i] >> 8);
    bytes[2 * i + 1] = static_cast<unsigned char>(image.values[i] & 0xff);
  }
  return WritePng(path, image.width, image.height, 16, PNG_COLOR_TYPE_GRAY, bytes);
}

Status WriteMaskPng(const std::string& path, const MaskImage& mask) {
  const size_t n = static_cast<size_t>(std::max(mask.width, 0)) * std::max(mask.height, 0);
  if (mask.values.size() != n) {
    return InvalidArgument(path + ": mask has " + std::to_string(mask.values.size()) +
                           " values, expected " + std::to_string(n));
  }
  return WritePng(path, mask.width, mask.height, 8, PNG_COLOR_TYPE_GRAY,
                  std::vector<unsigned char>(mask.values.begin(), mask.values.end()));
}

StatusOr<ImageSize> ReadPngSize(const std::string& path) {
  // Signature (8 bytes), IHDR length and type (8), width and height (4 + 4, big-endian).
  constexpr size_t kHeaderBytes = 24;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return NotFound(path + ": file does not exist");
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return DataLoss(path + ": cannot open file");
  unsigned char header[kHeaderBytes];
  const size_t got = std::fread(header, 1, kHeaderBytes, f);
  std::fclose(f);
  if (got != kHeaderBytes || png_sig_cmp(header, 0, kPngSignatureBytes) != 0 ||
      std::memcmp(header + 12, "IHDR", 4) != 0) {
    return DataLoss(path + ": not a PNG file (bad signature or header)");
  }
  auto be32 = [&](size_t at) {
    return (uint32_t{header[at]} << 24) | (uint32_t{header[at + 1]} << 16) | (uint32_t{header[at + 2]} << 8) |
           uint32_t{header[at + 3]};
  };
  const uint32_t width = be32(16), height = be32(20);
  if (width == 0 || height == 0 || width > static_cast<uint32_t>(limits::kMaxImageSide) ||
      height > static_cast<uint32_t>(limits::kMaxImageSide)) {
    return DataLoss(path + ": PNG header claims " + std::to_string(width) + "x" + std::to_string(height) +
                    " pixels (each side must be 1-" + std::to_string(limits::kMaxImageSide) + ")");
  }
  return ImageSize{static_cast<int>(width), static_cast<int>(height)};
}

StatusOr<ColourImage> ReadColourPng(const std::string& path) {
  PngReadState state;
  MCPOSE_RETURN_IF_ERROR(ReadPng(path, PngKind::kColour, "colour PNG must have 8-bit samples", &state));
  ColourImage image;
  image.width = static_cast<int>(state.width);
  image.height = static_cast<int>(state.height);
  image.rgba.assign(state.pixels.begin(), state.pixels.begin() + 4 * static_cast<size_t>(image.width) * image.height);
  return image;
}

Status WriteColourPng(const std::string& path, const ColourImage& image) {
  const size_t n = static_cast<size_t>(std::max(image.width, 0)) * std::max(image.height, 0);
  if (image.rgba.size() != 4 * n) {
    return InvalidArgument(path + ": image has " + std::to_string(image.rgba.size()) + " bytes, expected " +
                           std::to_string(4 * n));
  }
  bool opaque = true;
  for (size_t i = 0; i < n && opaque; ++i) opaque = image.rgba[4 * i + 3] == 255;
  if (!opaque) return WritePng(path, image.width, image.height, 8, PNG_COLOR_TYPE_RGB_ALPHA, image.rgba);
  std::vector<unsigned char> rgb(3 * n);
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) rgb[3 * i + c] = image.rgba[4 * i + c];
  return WritePng(path, image.width, image.height, 8, PNG_COLOR_TYPE_RGB, rgb);
}

}  // namespace mcpose::io

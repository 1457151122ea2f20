#include "mcpose/photometric.h"

#include <algorithm>
#include <array>
#include <functional>
#include <string>
#include <cmath>
#include <vector>

#include "mcpose/limits.h"
#include "core/rng.h"
#include "mcpose/io_util.h"
#include "io/jpeg_io.h"

namespace mcpose::synth {

namespace {

constexpr uint64_t kNoiseStream = 0x9015e;

uint8_t Clip8(double v) { return static_cast<uint8_t>(std::clamp(std::lround(v), 0l, 255l)); }

// The 256-entry table of a per-channel curve.
template <typename F>
std::array<uint8_t, 256> Table(F f) {
  std::array<uint8_t, 256> t{};
  for (int v = 0; v < 256; ++v) t[v] = f(static_cast<uint8_t>(v));
  return t;
}

void ApplyTables(const std::array<std::array<uint8_t, 256>, 3>& tables, ColourImage* image) {
  for (size_t i = 0; i < image->rgba.size(); i += 4)
    for (int c = 0; c < 3; ++c) image->rgba[i + c] = tables[c][image->rgba[i + c]];
}

}  // namespace

double SrgbToLinear(uint8_t value) {
  const double v = value / 255.0;
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

uint8_t LinearToSrgb(double linear) {
  const double l = std::clamp(linear, 0.0, 1.0);
  const double v = l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1 / 2.4) - 0.055;
  return Clip8(255.0 * v);
}

std::string PhotometricTransform::ToString() const {
  switch (kind) {
    case Kind::kNone: return "none";
    case Kind::kExposure: return "exposure:" + limits::Num(gain[0]);
    case Kind::kGamma: return "gamma:" + limits::Num(gamma);
    case Kind::kWhiteBalance:
      return "white-balance:" + limits::Num(gain[0]) + "," + limits::Num(gain[1]) + "," + limits::Num(gain[2]);
    case Kind::kSaturation: return "saturation:" + limits::Num(factor);
    case Kind::kClip: return "clip:" + limits::Num(level);
    case Kind::kJpeg: return "jpeg:" + std::to_string(quality);
    case Kind::kNoise: return "noise:" + limits::Num(sigma);
  }
  return "none";
}

StatusOr<PhotometricTransform> ParsePhotometricTransform(const std::string& spelling) {
  PhotometricTransform t;
  const size_t colon = spelling.find(':');
  const std::string name = spelling.substr(0, colon);
  const std::string arg = colon == std::string::npos ? "" : spelling.substr(colon + 1);
  const auto bad = [&](const std::string& why) {
    return InvalidArgument("photometric transform '" + spelling + "': " + why +
                           " (none, exposure:G, gamma:G, white-balance:R,G,B, saturation:F, clip:L, jpeg:Q, noise:S)");
  };
  std::vector<double> values;
  if (!arg.empty()) {
    for (std::string_view part : io::Split(arg, ',')) {
      double v = 0;
      if (!io::ParseDouble(part, &v) || !std::isfinite(v)) return bad("'" + std::string(part) + "' is not a number");
      values.push_back(v);
    }
  }
  const auto one = [&](double lo, double hi, bool open_lo, double* out) -> Status {
    if (values.size() != 1) return bad("expects one number");
    const double v = values[0];
    if ((open_lo ? v <= lo : v < lo) || v > hi)
      return bad(limits::Num(v) + " is not in " + (open_lo ? "(" : "[") + limits::Num(lo) + ", " + limits::Num(hi) + "]");
    *out = v;
    return Status::Ok();
  };
  if (name == "none") {
    if (!values.empty()) return bad("takes no number");
  } else if (name == "exposure") {
    t.kind = PhotometricTransform::Kind::kExposure;
    MCPOSE_RETURN_IF_ERROR(one(0, 16, true, &t.gain[0]));
  } else if (name == "gamma") {
    t.kind = PhotometricTransform::Kind::kGamma;
    MCPOSE_RETURN_IF_ERROR(one(0.1, 10, false, &t.gamma));
  } else if (name == "white-balance") {
    t.kind = PhotometricTransform::Kind::kWhiteBalance;
    if (values.size() != 3) return bad("expects three gains, red, green, blue");
    for (int c = 0; c < 3; ++c) {
      if (values[c] <= 0 || values[c] > 16) return bad("gain " + limits::Num(values[c]) + " is not in (0, 16]");
      t.gain[c] = values[c];
    }
  } else if (name == "saturation") {
    t.kind = PhotometricTransform::Kind::kSaturation;
    MCPOSE_RETURN_IF_ERROR(one(0, 16, false, &t.factor));
  } else if (name == "clip") {
    t.kind = PhotometricTransform::Kind::kClip;
    MCPOSE_RETURN_IF_ERROR(one(0, 1, true, &t.level));
  } else if (name == "jpeg") {
    t.kind = PhotometricTransform::Kind::kJpeg;
    double q = 0;
    MCPOSE_RETURN_IF_ERROR(one(1, 100, false, &q));
    if (q != std::floor(q)) return bad("the quality is a whole number");
    t.quality = static_cast<int>(q);
  } else if (name == "noise") {
    t.kind = PhotometricTransform::Kind::kNoise;
    MCPOSE_RETURN_IF_ERROR(one(0, 128, false, &t.sigma));
  } else {
    return bad("unknown transform '" + name + "'");
  }
  return t;
}

StatusOr<ColourImage> ApplyPhotometric(const PhotometricTransform& t, const ColourImage& image, uint64_t seed) {
  if (image.width <= 0 || image.height <= 0 || image.rgba.size() != 4 * static_cast<size_t>(image.width) * image.height)
    return InvalidArgument("photometric transform of an empty or inconsistent image");
  ColourImage out = image;
  using Kind = PhotometricTransform::Kind;
  switch (t.kind) {
    case Kind::kNone: break;
    case Kind::kExposure:
    case Kind::kWhiteBalance: {
      std::array<std::array<uint8_t, 256>, 3> tables;
      for (int c = 0; c < 3; ++c) {
        const double g = t.kind == Kind::kExposure ? t.gain[0] : t.gain[c];
        tables[c] = Table([g](uint8_t v) { return LinearToSrgb(g * SrgbToLinear(v)); });
      }
      ApplyTables(tables, &out);
      break;
    }
    case Kind::kGamma: {
      const auto table = Table([&](uint8_t v) { return Clip8(255.0 * std::pow(v / 255.0, t.gamma)); });
      ApplyTables({table, table, table}, &out);
      break;
    }
    case Kind::kClip: {
      const double top = std::round(255.0 * t.level);
      const auto table = Table([top](uint8_t v) { return static_cast<uint8_t>(std::min<double>(v, top)); });
      ApplyTables({table, table, table}, &out);
      break;
    }
    case Kind::kSaturation:
      for (size_t i = 0; i < out.rgba.size(); i += 4) {
        uint8_t* p = &out.rgba[i];
        const double luma = 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
        for (int c = 0; c < 3; ++c) p[c] = Clip8(luma + t.factor * (p[c] - luma));
      }
      break;
    case Kind::kJpeg: {
      MCPOSE_ASSIGN_OR_RETURN(std::string bytes, io::EncodeJpeg(image, t.quality));
      MCPOSE_ASSIGN_OR_RETURN(ColourImage decoded, io::DecodeJpeg(bytes, "(encoded in memory)"));
      for (size_t i = 0; i < out.rgba.size(); i += 4)
        for (int c = 0; c < 3; ++c) out.rgba[i + c] = decoded.rgba[i + c];
      break;
    }
    case Kind::kNoise:
      // One stream a row: the same image for a seed whatever the order rows are made in.
      for (int y = 0; y < out.height; ++y) {
        Rng rng(seed, kNoiseStream, static_cast<uint64_t>(y));
        uint8_t* row = out.rgba.data() + 4 * static_cast<size_t>(y) * out.width;
        for (int x = 0; x < out.width; ++x)
          for (int c = 0; c < 3; ++c) row[4 * x + c] = Clip8(row[4 * x + c] + t.sigma * rng.Normal());
      }
      break;
  }
  return out;
}

uint64_t PhotometricFrameSeed(uint64_t seed, const std::string& frame_name) {
  return HashCombine(seed, std::hash<std::string>{}(frame_name));
}

}  // namespace mcpose::synth

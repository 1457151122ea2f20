// Photometric transforms of a colour image: what lies between one camera's picture of a scene and
// another's (exposure, white balance, the tone curve, saturation, clipping, compression, sensor
// noise), applied to a frame with its depth untouched. They test whether the colour term of the
// weight holds in other light (scripts/accuracy_photometric.sh) and make a synthetic frame look
// like a camera's (mcpose synth).
//
// Exposure and white balance act on linear light (the sRGB transfer curve undone, scaled, redone),
// as a camera's would; gamma, saturation and clipping act on the 8-bit values as stored.
#pragma once

#include <cstdint>
#include <string>

#include "mcpose/image.h"
#include "mcpose/status.h"

namespace mcpose::synth {

struct PhotometricTransform {
  enum class Kind {
    kNone,          // the image as it is
    kExposure,      // linear light times `gain[0]`, clipped
    kGamma,         // v -> 255 (v / 255)^gamma
    kWhiteBalance,  // linear red, green, blue times gain[0..2], clipped
    kSaturation,    // each channel drawn towards (factor < 1) or away from its pixel's luma (Rec. 601)
    kClip,          // values above `level` * 255 clipped to it
    kJpeg,          // encoded as JPEG of `quality` and decoded
    kNoise,         // Gaussian noise of `sigma` levels per channel and pixel, rounded and clipped
  };
  Kind kind = Kind::kNone;
  double gain[3] = {1, 1, 1};
  double gamma = 1;
  double factor = 1;
  double level = 1;
  int quality = 100;
  double sigma = 0;

  // The spelling Parse reads: "none", "exposure:0.5", "gamma:1.6", "white-balance:1.3,1,0.7",
  // "saturation:0.5", "clip:0.8", "jpeg:30", "noise:8".
  std::string ToString() const;
};

// One transform from its spelling (PhotometricTransform::ToString), with bounds: gains and the
// saturation factor in (0, 16], gamma in [0.1, 10], clip level in (0, 1], JPEG quality 1-100,
// noise sigma in [0, 128]. An error names the spelling and what is wrong.
StatusOr<PhotometricTransform> ParsePhotometricTransform(const std::string& spelling);

// The noise seed of one frame of a relit dataset: `seed` combined with a hash of the frame's name
// ("<video>/<file>"), so each frame has its own noise, the same whatever else the dataset holds.
uint64_t PhotometricFrameSeed(uint64_t seed, const std::string& frame_name);

// `image` transformed; alpha is kept. Deterministic for `seed` (only kNoise draws).
StatusOr<ColourImage> ApplyPhotometric(const PhotometricTransform& transform, const ColourImage& image,
                                       uint64_t seed);

// sRGB transfer curve: 8-bit value to linear light in [0, 1], and back (rounded, clipped).
double SrgbToLinear(uint8_t value);
uint8_t LinearToSrgb(double linear);

}  // namespace mcpose::synth

// The ranges a real sensor or dataset can produce, checked by every file reader at the
// boundary. A value outside them is refused with a message naming the file and the field;
// nothing past the readers needs to guard against it. docs/usage.md ("Input checking") states
// the same limits for users.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include <Eigen/Core>

#include "mcpose/options.h"  // limits::kMaxBoxesPerImage

namespace mcpose::limits {

// Images: the largest side of any image read (depth, colour, label, texture), checked against
// the header before a pixel buffer is allocated.
inline constexpr int kMaxImageSide = 16384;

// Intrinsics: focal lengths in pixels.
inline constexpr double kMinFocalPx = 1.0;
inline constexpr double kMaxFocalPx = 100000.0;

// Depth scale: the largest 16-bit depth value, 65535 units, must lie between 1 cm and 100 m.
inline constexpr double kMinDepthRangeM = 0.01;
inline constexpr double kMaxDepthRangeM = 100.0;
inline constexpr uint16_t kSaturatedDepth = 65535;  // a sensor's "out of range": no measurement

// Mesh vertices, evaluation points and pose translations: finite and under 100 m in every
// coordinate.
inline constexpr double kMaxCoordinateM = 100.0;

// Rotations: max |R^T R - I| and |det R - 1| at most this (what a text file of 9 numbers carries).
inline constexpr double kRotationTolerance = 1e-3;

// MAT-file variables: at most this many elements (a YCB-Video meta.mat holds a few hundred).
inline constexpr size_t kMaxMatElements = size_t{1} << 20;

// Any input file: a regular file (not a device, pipe or folder, also behind a link) of at most
// this many bytes (the largest real input, a 4096 x 4096 texture or a scan's mesh, is tens of MB).
inline constexpr int64_t kMaxFileBytes = int64_t{1} << 31;

// JSON: objects and arrays nested at most this deep (BOP files nest 3-4 levels).
inline constexpr int kMaxJsonDepth = 64;

// Detector boxes: corner and sides within this many pixels of the origin.
inline constexpr double kMaxBoxPx = 4.0 * kMaxImageSide;

// "%g" of a value, for messages.
inline std::string Num(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

// Empty if 1 <= f <= 100,000 px, else what is wrong with focal length `name`.
inline std::string CheckFocal(const char* name, double f) {
  if (std::isfinite(f) && f >= kMinFocalPx && f <= kMaxFocalPx) return {};
  return std::string(name) + " = " + Num(f) + " px is outside " + Num(kMinFocalPx) + "-" + Num(kMaxFocalPx) + " px";
}

// Empty if the largest 16-bit value times `metres_per_unit` lies in 1 cm-100 m.
inline std::string CheckDepthScale(double metres_per_unit) {
  const double largest_m = 65535.0 * metres_per_unit;
  if (std::isfinite(largest_m) && largest_m >= kMinDepthRangeM && largest_m <= kMaxDepthRangeM) return {};
  return "depth scale " + Num(metres_per_unit) + " m per unit puts the largest depth at " + Num(largest_m) +
         " m, outside " + Num(kMinDepthRangeM) + "-" + Num(kMaxDepthRangeM) + " m";
}

// True if `v` is finite and under 100 m in magnitude.
inline bool CoordinateOk(double v) { return std::isfinite(v) && std::abs(v) < kMaxCoordinateM; }

// Empty if each coordinate of `p` (metres) is finite and under 100 m, else the problem.
template <typename Derived>
std::string CheckCoordinates(const Eigen::MatrixBase<Derived>& p) {
  for (int k = 0; k < p.size(); ++k) {
    if (!CoordinateOk(static_cast<double>(p(k)))) {
      return std::string(1, "xyz"[k % 3]) + " = " + Num(static_cast<double>(p(k))) +
             " m is not finite or not under " + Num(kMaxCoordinateM) + " m";
    }
  }
  return {};
}

// Empty if `R` is a rotation (orthonormal, det +1, within kRotationTolerance), else the numbers.
inline std::string CheckRotation(const Eigen::Matrix3d& R) {
  const double off = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  const double det = R.determinant();
  if (off <= kRotationTolerance && std::abs(det - 1.0) <= kRotationTolerance) return {};
  char text[128];
  std::snprintf(text, sizeof text, "R is not a rotation: max |R^T R - I| = %.3g, det = %.6g (tolerance %g)", off, det,
                kRotationTolerance);
  return text;
}

// A pinhole camera matrix K (row-major 3 x 3, pixels) for an image of width x height:
// [fx 0 cx; 0 fy cy; 0 0 1], focal lengths within kMinFocalPx-kMaxFocalPx, the principal point
// inside the image. Empty if K is one, else the problem. Every reader of intrinsics and the
// Python entry points check K here.
inline std::string CheckPinholeMatrix(const double* K, int width, int height) {
  for (int i = 0; i < 9; ++i)
    if (!std::isfinite(K[i]))
      return "K[" + std::to_string(i / 3) + "][" + std::to_string(i % 3) + "] = " + Num(K[i]) + " is not finite";
  if (K[1] != 0 || K[3] != 0 || K[6] != 0 || K[7] != 0 || K[8] != 1)
    return "not a pinhole matrix [fx 0 cx; 0 fy cy; 0 0 1] (no skew, last row 0 0 1)";
  if (std::string problem = CheckFocal("fx", K[0]); !problem.empty()) return problem;
  if (std::string problem = CheckFocal("fy", K[4]); !problem.empty()) return problem;
  if (!(K[2] >= 0 && K[2] <= width && K[5] >= 0 && K[5] <= height))
    return "principal point (" + Num(K[2]) + ", " + Num(K[5]) + ") lies outside the " + std::to_string(width) + "x" +
           std::to_string(height) + " image";
  return {};
}

// Depth in metres, row-major width x height: each value 0 (no measurement) or positive and finite
// up to kMaxDepthRangeM. Empty if every value is, else the first that is not.
inline std::string CheckDepthMetres(const float* depth, int width, int height) {
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float v = depth[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)];
      if (!(v >= 0 && v <= kMaxDepthRangeM))
        return "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") = " + Num(v) +
               " m; depth is 0 (no measurement) or positive and finite up to " + Num(kMaxDepthRangeM) + " m";
    }
  return {};
}

}  // namespace mcpose::limits

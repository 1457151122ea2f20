// Scoring one rendered hypothesis against the observed depth inside its box.
//
// The scorer takes depth spans, never meshes: `rendered` is the z-buffer of the box (+inf where
// nothing was drawn) and `observed` the observed depth of the same box (0 where invalid),
// both metres, row-major with the box width as stride.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "mcpose/camera.h"
#include "render/raster.h"
#include "score/colour.h"

namespace mcpose::score {

struct InlierCounts {
  int32_t inliers = 0;   // N
  int32_t rendered = 0;  // N_r
  int32_t observed = 0;  // N_b
  int32_t occluded = 0;  // rendered non-inlier pixels whose observed depth lies in front by >= eps
  ColourStats colour;    // over the depth inliers, when the colour test ran (score/colour.h)
  bool operator==(const InlierCounts&) const = default;
};

// Valid observed pixels (depth > 0) of a box: N_b. Independent of the hypothesis.
int32_t CountObserved(std::span<const float> observed);

// The paper's 1-D test: N counts pixels with |z_rendered - z_observed| < eps_m, observed > 0;
// `occluded` counts rendered pixels with z_observed <= z_rendered - eps_m (something in front).
InlierCounts CountInliers1D(std::span<const float> rendered, std::span<const float> observed,
                            float eps_m);

// The same counts as CountInliers1D over a whole box, reading only the sub-rectangle `rect`
// of it (box-relative pixels, row stride `stride`) outside which nothing was rendered, with
// N_b given (it does not depend on the hypothesis). `rendered` outside `rect` is not read.
InlierCounts CountInliers1DInRect(const float* rendered, const float* observed, int stride,
                                  const render::PixelRect& rect, int32_t n_observed, float eps_m);

// `observed` with NaN for every invalid pixel (depth not > 0): the form the SIMD counter
// reads, where a comparison with NaN is false, so validity needs no test of its own.
std::vector<float> ObservedOrNaN(std::span<const float> observed);

// CountInliers1DInRect a vector of pixels at a time (Highway: AVX-512, AVX2, SSE4 or scalar,
// chosen at run time) on `observed_or_nan` (ObservedOrNaN of the box's observed depth); the
// same counts (inlier_simd.cc, tested on every target).
InlierCounts CountInliers1DInRectSimd(const float* rendered, const float* observed_or_nan, int stride,
                                      const render::PixelRect& rect, int32_t n_observed, float eps_m);

// The 3-D reference test: the observed pixels of one box back-projected to camera-frame points
// in a KD-tree; a rendered pixel is an inlier if its back-projected point has an observed point
// within eps. Built once per box, then queried by any number of hypotheses (thread-safe).
class ObservedCloud {
 public:
  ObservedCloud(const Intrinsics& K, const render::PixelRect& box, std::span<const float> observed);
  ~ObservedCloud();
  ObservedCloud(const ObservedCloud&) = delete;
  ObservedCloud& operator=(const ObservedCloud&) = delete;

  InlierCounts CountInliers3D(std::span<const float> rendered, float eps_m) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mcpose::score

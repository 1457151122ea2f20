// The tracker's motion model: the last frame's posterior carried into the next frame. Samples
// are drawn from the weighted posterior (the estimator's CDF sampler) and each is moved by
// Gaussian noise in 6-DoF (filter::Diffuse: translation in the camera frame, rotation about the
// object's origin).
#pragma once

#include <cstdint>

#include "filter/particles.h"

namespace mcpose::track {

struct MotionModel {
  double sigma_t_m = 0.01;     // per-axis translation noise per frame
  double sigma_r_rad = 0.05;   // per-axis rotation noise per frame (axis-angle)
  int cdf_table_size = 64;     // the resampler's coarse table (ResampleOptions::cdf_table_size)
};

// `n` samples for the next frame from `posterior` (weights finite and >= 0; all zero: drawn
// uniformly), every one rendered in box 0. Sample i depends only on (seed, stream_id, i), so
// the result is the same at any thread count.
filter::ParticleSet PredictSamples(const filter::ParticleSet& posterior, const MotionModel& motion, int n,
                                   uint64_t seed, uint64_t stream_id);

}  // namespace mcpose::track

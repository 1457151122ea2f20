// Steps 4 and 5 of the filter: the next generation of samples, each drawn from the current one
// by the CDF-table resampler, turned by a flip move now and then, and diffused.
#pragma once

#include <cstdint>

#include <Eigen/Core>

#include "core/parallel_for.h"
#include "filter/particles.h"
#include "filter/resample.h"

namespace mcpose::filter {

struct DiffusionStep {
  double sigma_r_rad = 0;  // this iteration's rotation noise (tangent space), radians
  double sigma_t_m = 0;    // this iteration's translation noise, metres
  double flip_rate = 0;    // probability of a flip move before the noise
  Eigen::Vector3d flip_center = Eigen::Vector3d::Zero();  // model point the flips turn about
};

// The noise of iteration k: max(sigma_min, sigma_0 * anneal^k).
double AnnealedSigma(double sigma_0, double sigma_min, double anneal, int k);

// The next generation, of `count` samples: next[i] for i < elites is the i-th heaviest sample
// of `current` as it is (elites at most the samples `sampler` keeps); every other next[i] is the
// sample `sampler` draws for u_i, maybe flipped, diffused. Each keeps its parent's box. Sample i
// draws from its own stream Rng(seed, stream, substream, i): u_i, then (with flips on) the flip,
// then the noise. Runs on `pool`; any split gives the same samples. Returns the CDF reads of
// the draws.
int64_t NextGeneration(const ParticleSet& current, const CdfSampler& sampler, const DiffusionStep& step,
                       uint64_t seed, uint64_t stream, uint64_t substream, int count, int elites, ThreadPool& pool,
                       ParticleSet* next);

}  // namespace mcpose::filter

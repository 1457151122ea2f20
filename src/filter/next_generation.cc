#include "filter/next_generation.h"

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

#include "core/check.h"
#include "core/rng.h"
#include "filter/diffuse.h"

namespace mcpose::filter {

double AnnealedSigma(double sigma_0, double sigma_min, double anneal, int k) {
  return std::max(sigma_min, sigma_0 * std::pow(anneal, k));
}

int64_t NextGeneration(const ParticleSet& p, const CdfSampler& sampler, const DiffusionStep& step,
                       uint64_t seed, uint64_t stream, uint64_t substream, int count, int elites, ThreadPool& pool,
                       ParticleSet* next) {
  MCPOSE_CHECK_GE(count, 0);
  MCPOSE_CHECK_GE(elites, 0);
  const std::span<const int> best = sampler.sorted_indices();
  const int64_t n = count, kept = std::min<int64_t>({elites, count, static_cast<int64_t>(best.size())});
  next->Resize(static_cast<size_t>(n));
  std::vector<int64_t> reads(static_cast<size_t>(pool.size()), 0);  // per worker
  pool.ParallelFor(n, [&](int64_t begin, int64_t end, int worker) {
    int64_t r = 0;
    for (int64_t i = begin; i < end; ++i) {
      if (i < kept) {
        const int e = best[static_cast<size_t>(i)];
        next->R_cam_obj[i] = p.R_cam_obj[e], next->t_cam_obj_m[i] = p.t_cam_obj_m[e], next->box[i] = p.box[e];
        continue;
      }
      Rng rng(seed, stream, substream, static_cast<uint64_t>(i));
      const int parent = sampler.Draw(rng.Uniform(), &r);
      Eigen::Matrix3d R = p.R_cam_obj[parent];
      Eigen::Vector3d t = p.t_cam_obj_m[parent];
      // A flip move draws only when enabled: flip_rate 0 gives the samples of a filter without.
      if (step.flip_rate > 0 && rng.Uniform() < step.flip_rate)
        Flip(std::min(2, static_cast<int>(3 * rng.Uniform())), step.flip_center, &R, &t);
      Diffuse(R, t, step.sigma_r_rad, step.sigma_t_m, rng, &next->R_cam_obj[i], &next->t_cam_obj_m[i]);
      next->box[i] = p.box[parent];
    }
    reads[static_cast<size_t>(worker)] += r;
  });
  int64_t total = 0;
  for (int64_t r : reads) total += r;
  return total;
}

}  // namespace mcpose::filter

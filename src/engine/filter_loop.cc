#include "engine/filter_loop.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "engine/initialize.h"
#include "filter/next_generation.h"
#include "filter/resample.h"

namespace mcpose::engine {

namespace {

// Substream of the per-sample random streams of resampling + diffusion (plus the iteration).
constexpr uint64_t kStepStream = 0xD1FF05E;

using Clock = std::chrono::steady_clock;
double MsSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

}  // namespace

int EliteCount(const EstimatorOptions& options, int generation) {
  return std::clamp(static_cast<int>(std::lround(options.resample.elite_share * generation)), 0, generation);
}

ObjectEstimate RunFilter(BoxScorer& scorer, const EstimatorOptions& opt, ThreadPool& pool, uint64_t stream_id,
                         const IterationObserver& observer, const filter::ParticleSet* start) {
  ObjectEstimate result;
  result.obj_id = scorer.obj_id();
  result.best_weight = -1;
  for (int b = 0; b < scorer.num_boxes(); ++b)
    result.box_triangles.push_back(static_cast<int>(scorer.box_mesh(b).triangles.size()));
  result.depth_pixels_read = scorer.depth_pixels_read();
  result.colour = scorer.uses_colour();
  const Mesh& mesh = scorer.mesh();
  filter::DiffusionStep step;
  step.flip_rate = opt.diffusion.flip_rate;
  step.flip_center = (0.5f * (mesh.BoundsMin() + mesh.BoundsMax())).cast<double>();

  // 1. Initialize: samples over the boxes in proportion to score, init.wide times as many in
  // the first generation as in the others (or the given start, of the size every generation has).
  filter::ParticleSet particles[2];
  if (start) {
    particles[0] = *start;
  } else {
    InitializeSamples(scorer, opt, stream_id, &particles[0], opt.samples * opt.init.wide);
  }
  const int n = start ? static_cast<int>(start->size()) : opt.samples;
  const int elites = EliteCount(opt, n);  // the kept samples (validated: elite <= keep-top) hold them
  filter::CdfSampler sampler;
  for (int iter = 0, cur = 0; iter < opt.max_iterations; ++iter, cur = 1 - cur) {
    filter::ParticleSet& p = particles[cur];
    IterationSummary& it = result.iterations.emplace_back();
    const Clock::time_point start = Clock::now();

    // 2-3. Render each sample in its box, count its inliers, weigh it (the colour term's weight
    // ramped up over the first iterations; the answer comes from those at the full weight).
    const int ramp = scorer.uses_colour() ? opt.appearance.ramp_iterations : 0;
    const bool full_weight = iter + 1 >= ramp || iter + 1 == opt.max_iterations;
    scorer.Weigh(&p, &it.counters, full_weight ? -1.0 : opt.appearance.weight * (iter + 1) / ramp);
    it.score_ms = MsSince(start);
    if (observer) observer(iter, p);
    double sum = 0;
    it.best_weight = -1;
    for (size_t i = 0; i < p.size(); ++i) {
      sum += p.weight[i];
      it.best_weight = std::max(it.best_weight, p.weight[i]);
      if (full_weight && p.weight[i] > result.best_weight) {  // ties: the earliest sample seen
        result.best_weight = p.weight[i];
        result.T_cam_obj = p.Pose(i);
        result.best_box = p.box[i];
      }
    }
    it.mean_weight = sum / static_cast<double>(p.size());

    // 6. Stop when the samples agree with the frame well enough (or at the limit).
    if (it.mean_weight > opt.tau || iter + 1 == opt.max_iterations) {
      it.iteration_ms = MsSince(start);
      break;
    }
    // 4. Resample by the sorted CDF and its coarse table; 5. diffuse into the other buffer.
    sampler.Build(p.weight, opt.resample.keep_top_fraction, opt.resample.cdf_table_size);
    const DiffusionOptions& d = opt.diffusion;
    step.sigma_r_rad = filter::AnnealedSigma(d.sigma_r_rad, d.sigma_r_min_rad, d.anneal, iter);
    step.sigma_t_m = filter::AnnealedSigma(d.sigma_t_m, d.sigma_t_min_m, d.anneal, iter);
    it.counters.cdf_reads += filter::NextGeneration(p, sampler, step, opt.seed, stream_id,
                                                    kStepStream + static_cast<uint64_t>(iter), n, elites, pool,
                                                    &particles[1 - cur]);
    it.counters.cdf_draws += n - std::min(elites, static_cast<int>(sampler.sorted_indices().size()));
    it.iteration_ms = MsSince(start);
  }
  return result;
}

}  // namespace mcpose::engine

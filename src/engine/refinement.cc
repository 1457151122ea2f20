#include "engine/refinement.h"

#include <algorithm>
#include <chrono>

namespace mcpose::engine {

refine::AlignOptions AlignSettings(const RefineOptions& options, int iterations) {
  refine::AlignOptions a;
  a.max_iterations = iterations;
  a.tukey_m = options.tukey_m;
  a.max_distance_m = options.max_distance_m;
  return a;
}

ObjectEstimate RefineEstimate(const RefineOptions& options, BoxScorer& full, const DepthImage& depth,
                              ObjectEstimate estimate) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  RefineRecord& r = estimate.refine;
  r.ran = true;
  const refine::AlignResult aligned =
      refine::AlignToDepth(full.K(), depth, full.box_observation(0).image_rect, full.mesh(), estimate.T_cam_obj,
                           AlignSettings(options, options.max_iterations));
  r.iterations = aligned.iterations;
  r.pairs = aligned.pairs;
  r.rms_before_m = aligned.rms_before_m, r.rms_after_m = aligned.rms_after_m;
  // The estimator's own measure, at full resolution, of the start and of every step's pose:
  // the best of them is kept (ties: the later, more aligned one), so the weight never drops.
  // Its inliers are counted within options.accept_eps_m: at the filter's centimetre the count
  // changes between such close poses only at the object's outline, and the filter's answer,
  // the best of many noisy samples, keeps it nearly always, even where the aligned pose lies
  // millimetres closer to the surface.
  filter::ParticleSet poses;
  poses.Resize(aligned.path.size() + 1);
  poses.R_cam_obj[0] = estimate.T_cam_obj.R, poses.t_cam_obj_m[0] = estimate.T_cam_obj.t;
  for (size_t i = 0; i < aligned.path.size(); ++i)
    poses.R_cam_obj[i + 1] = aligned.path[i].R, poses.t_cam_obj_m[i + 1] = aligned.path[i].t;
  std::fill(poses.box.begin(), poses.box.end(), 0);
  EngineCounters counters;
  const float filter_eps = full.inlier_threshold();
  if (options.accept_eps_m > 0) full.set_inlier_threshold(static_cast<float>(options.accept_eps_m));
  full.Weigh(&poses, &counters);
  full.set_inlier_threshold(filter_eps);
  size_t best = 0;
  for (size_t i = 1; i < poses.size(); ++i)
    if (poses.weight[i] >= poses.weight[best]) best = i;
  r.weight_before = poses.weight[0], r.weight_after = poses.weight[best];
  r.accepted = best > 0;
  if (r.accepted) estimate.T_cam_obj = poses.Pose(best);
  r.ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  return estimate;
}

}  // namespace mcpose::engine

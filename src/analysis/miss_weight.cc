#include "mcpose/analysis/miss_weight.h"

#include <iterator>
#include <limits>
#include <memory>
#include <numbers>
#include <vector>

#include <Eigen/Geometry>

#include "analysis/scorer.h"
#include "engine/box_scorer.h"
#include "engine/refinement.h"
#include "refine/align.h"

namespace mcpose::analysis {

StatusOr<MissWeight> WeighMiss(Scorer& weigher, const Intrinsics& K, const DepthImage& depth,
                               const ColourImage* colour, const Mesh& mesh, std::span<const Detection> boxes,
                               const SE3& T_est, const SE3& T_gt, bool as_filter) {
  engine::Context& context = weigher.impl().context;
  const EstimatorOptions& o = context.options();
  const refine::AlignOptions align = engine::AlignSettings(o.refine, o.refine.max_iterations);
  const engine::Resolution resolution = as_filter ? engine::Resolution::kEngine : engine::Resolution::kFull;
  if (boxes.empty()) return InvalidArgument("no box to weigh the estimate and the truth in");
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<engine::BoxScorer> scorer,
                          engine::BoxScorer::Create(context, K, depth, mesh, boxes, colour, resolution));
  // Per box b: sample 2b the estimate, 2b + 1 the truth aligned in that box.
  const int n = scorer->num_boxes();
  filter::ParticleSet poses;
  poses.Resize(static_cast<size_t>(2 * n));
  std::vector<SE3> aligned(static_cast<size_t>(n));
  for (int b = 0; b < n; ++b) {
    aligned[static_cast<size_t>(b)] =
        refine::AlignToDepth(K, depth, scorer->box_observation(b).image_rect, mesh, T_gt, align).T_cam_obj;
    const size_t e = static_cast<size_t>(2 * b), t = e + 1;
    poses.R_cam_obj[e] = T_est.R, poses.t_cam_obj_m[e] = T_est.t, poses.box[e] = b;
    poses.R_cam_obj[t] = aligned[static_cast<size_t>(b)].R, poses.t_cam_obj_m[t] = aligned[static_cast<size_t>(b)].t;
    poses.box[t] = b;
  }
  EngineCounters counters;
  scorer->Weigh(&poses, &counters);
  MissWeight out;
  out.estimate_weight = out.truth_weight = -1;
  for (int b = 0; b < n; ++b) {
    const double we = poses.weight[static_cast<size_t>(2 * b)], wt = poses.weight[static_cast<size_t>(2 * b + 1)];
    if (we > out.estimate_weight) out.estimate_weight = we, out.estimate_box = b;
    if (wt > out.truth_weight) out.truth_weight = wt, out.truth_box = b, out.truth_aligned = aligned[static_cast<size_t>(b)];
  }
  if (!out.search_failure()) return out;

  // ---- The basin: the aligned truth turned about each model axis and moved along each camera
  // axis by each step, weighed in its box -----------------------------------------------------
  const SE3& T = out.truth_aligned;
  const Eigen::Vector3d centre = (0.5f * (mesh.BoundsMin() + mesh.BoundsMax())).cast<double>();
  constexpr int kSteps = static_cast<int>(std::size(kBasinSteps));
  filter::ParticleSet probes;
  probes.Resize(static_cast<size_t>(2 * 3 * kSteps));
  for (int s = 0; s < kSteps; ++s) {
    for (int axis = 0; axis < 3; ++axis) {
      const Eigen::Matrix3d S =
          Eigen::AngleAxisd(kBasinSteps[s] * std::numbers::pi / 180, Eigen::Vector3d::Unit(axis)).toRotationMatrix();
      const size_t turn = static_cast<size_t>(3 * s + axis), move = static_cast<size_t>(3 * (kSteps + s) + axis);
      // X -> S (X - c) + c in the model frame, then T.
      probes.R_cam_obj[turn] = T.R * S, probes.t_cam_obj_m[turn] = T.R * (centre - S * centre) + T.t;
      probes.R_cam_obj[move] = T.R, probes.t_cam_obj_m[move] = T.t + kBasinSteps[s] / 1000 * Eigen::Vector3d::Unit(axis);
    }
  }
  std::fill(probes.box.begin(), probes.box.end(), out.truth_box);
  scorer->Weigh(&probes, &counters);
  const auto first_step_below = [&](int kind) {  // kind 0: turns, 1: moves
    for (int s = 0; s < kSteps; ++s)
      for (int axis = 0; axis < 3; ++axis)
        if (probes.weight[static_cast<size_t>(3 * (kind * kSteps + s) + axis)] <= out.estimate_weight)
          return kBasinSteps[s];
    return std::numeric_limits<double>::infinity();
  };
  out.basin_turn_deg = first_step_below(0);
  out.basin_shift_mm = first_step_below(1);
  return out;
}

}  // namespace mcpose::analysis

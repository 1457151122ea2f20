#include "mcpose/analysis/miss_weight.h"

#include <memory>
#include <vector>

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
  return out;
}

}  // namespace mcpose::analysis

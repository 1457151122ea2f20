#include "mcpose/analysis/twin_margin.h"

#include <algorithm>
#include <memory>

#include "analysis/scorer.h"
#include "engine/box_scorer.h"
#include "engine/refinement.h"
#include "engine/twins.h"
#include "mcpose/eval.h"
#include "refine/align.h"
#include "score/weight.h"

namespace mcpose::analysis {

namespace {

// The twin candidates of `centre` (itself first: as it is, or aligned to the depth with
// `align_centre` where that is given; the others aligned with the twin alignment's settings),
// weighed together in `box` at full resolution.
struct WeighedTwins {
  std::unique_ptr<engine::BoxScorer> scorer;
  std::vector<SE3> candidates;
  filter::ParticleSet poses;
};

StatusOr<WeighedTwins> WeighTwins(engine::Context& context, const Intrinsics& K, const DepthImage& depth,
                                  const ColourImage* colour, const Mesh& mesh, const Detection& box,
                                  const SE3& centre, const refine::AlignOptions* align_centre) {
  const EstimatorOptions& opt = context.options();
  WeighedTwins out;
  MCPOSE_ASSIGN_OR_RETURN(out.scorer, engine::BoxScorer::Create(context, K, depth, mesh, std::span(&box, 1), colour,
                                                                engine::Resolution::kFull));
  const render::PixelRect rect = out.scorer->box_observation(0).image_rect;
  const refine::AlignOptions align = engine::AlignSettings(opt.refine, opt.refine.twin_iterations);
  const SE3 first = align_centre ? refine::AlignToDepth(K, depth, rect, mesh, centre, *align_centre).T_cam_obj : centre;
  out.candidates = engine::TwinCandidates(first, mesh, opt.appearance.twin_step_deg);
  for (size_t i = 1; i < out.candidates.size(); ++i)
    out.candidates[i] = refine::AlignToDepth(K, depth, rect, mesh, out.candidates[i], align).T_cam_obj;
  out.poses.Resize(out.candidates.size());
  for (size_t i = 0; i < out.candidates.size(); ++i)
    out.poses.R_cam_obj[i] = out.candidates[i].R, out.poses.t_cam_obj_m[i] = out.candidates[i].t, out.poses.box[i] = 0;
  EngineCounters counters;
  out.scorer->Weigh(&out.poses, &counters);
  return out;
}

}  // namespace

bool TwinMarginOptions::IsValid(std::string* error) const {
  if (!(right_m > 0) || !(wrong_m >= right_m)) {
    *error = "need 0 < right_m <= wrong_m";
    return false;
  }
  return true;
}

StatusOr<TwinMargin> MeasureTwinMargin(Scorer& scorer, const Intrinsics& K, const DepthImage& depth,
                                       const ColourImage* colour, const Mesh& mesh, const Detection& box,
                                       const SE3& T_gt, std::span<const Eigen::Vector3f> points, bool symmetric,
                                       const TwinMarginOptions& options) {
  engine::Context& context = scorer.impl().context;
  std::string error;
  if (!options.IsValid(&error)) return InvalidArgument("twin margin options: " + error);
  const EstimatorOptions& opt = context.options();
  // The truth itself, aligned to the depth with the refinement's settings, is the first candidate.
  const refine::AlignOptions align_truth = engine::AlignSettings(opt.refine, opt.refine.max_iterations);
  MCPOSE_ASSIGN_OR_RETURN(WeighedTwins twins, WeighTwins(context, K, depth, colour, mesh, box, T_gt, &align_truth));
  const std::vector<SE3>& candidates = twins.candidates;
  const filter::ParticleSet& poses = twins.poses;
  const std::span<const score::InlierCounts> counts = twins.scorer->last_counts();
  const std::vector<Eigen::Vector3f> pts(points.begin(), points.end());

  TwinMargin out;
  out.colour = twins.scorer->uses_colour();
  out.candidates = static_cast<int>(candidates.size());
  constexpr double kNone = -1e9;
  double right[3] = {kNone, kNone, kNone}, wrong[3] = {kNone, kNone, kNone};
  int right_best = -1;
  for (size_t i = 0; i < candidates.size(); ++i) {
    const double e = symmetric ? AddS(pts, candidates[i], T_gt) : Add(pts, candidates[i], T_gt);
    const double w[3] = {poses.weight[i], score::Weight(counts[i], box.score, opt.weight),
                         score::VisibleColourAgreement(counts[i], opt.appearance)};
    if (e < options.right_m) {
      if (w[0] > right[0]) right_best = static_cast<int>(i);
      for (int k = 0; k < 3; ++k) right[k] = std::max(right[k], w[k]);
    } else if (e >= options.wrong_m) {
      ++out.wrong;
      for (int k = 0; k < 3; ++k) wrong[k] = std::max(wrong[k], w[k]);
    }
  }
  if (right_best < 0) return Internal("the truth aligned to the depth lies farther than right_m from the truth");
  out.colour_pixels = static_cast<int>(counts[static_cast<size_t>(right_best)].colour.n);
  if (out.wrong > 0) {
    out.margin = right[0] - wrong[0];
    out.depth_margin = right[1] - wrong[1];
    out.colour_margin = right[2] - wrong[2];
  }
  return out;
}

StatusOr<TwinReach> MeasureTwinReach(Scorer& scorer, const Intrinsics& K, const DepthImage& depth,
                                     const ColourImage* colour, const Mesh& mesh, const Detection& box,
                                     const SE3& T_est, const SE3& T_gt, std::span<const Eigen::Vector3f> points,
                                     bool symmetric) {
  engine::Context& context = scorer.impl().context;
  MCPOSE_ASSIGN_OR_RETURN(WeighedTwins twins, WeighTwins(context, K, depth, colour, mesh, box, T_est, nullptr));
  const std::vector<SE3>& candidates = twins.candidates;
  const filter::ParticleSet& poses = twins.poses;
  const std::vector<Eigen::Vector3f> pts(points.begin(), points.end());
  TwinReach out;
  out.nearest_m = 1e9;
  out.estimate_weight = poses.weight[0];
  out.best_weight = -1;
  for (size_t i = 0; i < candidates.size(); ++i) {
    const double e = symmetric ? AddS(pts, candidates[i], T_gt) : Add(pts, candidates[i], T_gt);
    if (e < out.nearest_m) out.nearest_m = e, out.nearest_weight = poses.weight[i];
    if (poses.weight[i] > out.best_weight) out.best_weight = poses.weight[i], out.best_m = e;
  }
  return out;
}

}  // namespace mcpose::analysis

#include "engine/estimate.h"

#include "engine/box_scorer.h"
#include "engine/filter_loop.h"
#include "engine/refinement.h"
#include "engine/twins.h"

namespace mcpose::engine {

void MoveSamples(const SE3& from, const SE3& to, filter::ParticleSet* samples) {
  const SE3 correction = to * from.Inverse();
  for (size_t i = 0; i < samples->size(); ++i) {
    const SE3 moved = correction * samples->Pose(i);
    samples->R_cam_obj[i] = moved.R, samples->t_cam_obj_m[i] = moved.t;
  }
}

StatusOr<ObjectEstimate> EstimateObject(Context& context, const Intrinsics& K, const DepthImage& depth,
                                        const ColourImage* colour, const Mesh& mesh, std::span<const Detection> boxes,
                                        uint64_t stream_id, filter::ParticleSet* posterior) {
  const SimdScopeGuard simd(context);
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<BoxScorer> scorer, BoxScorer::Create(context, K, depth, mesh, boxes, colour));
  const EstimatorOptions& opt = context.options();
  const auto keep_last = [posterior](int, const filter::ParticleSet& weighted) {
    if (posterior) *posterior = weighted;
  };
  ObjectEstimate estimate = RunFilter(*scorer, opt, context.pool(), stream_id, keep_last);
  const SE3 filtered = estimate.T_cam_obj;
  const bool twins = scorer->uses_colour() && opt.appearance.resolve_twins;
  if (twins || opt.refine.enabled) {
    // Twin resolution and refinement judge poses finely: every pixel of the chosen box, the
    // full mesh, with colour where the filter had it.
    const Detection chosen = scorer->detection(estimate.best_box);
    MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<BoxScorer> full,
                            BoxScorer::Create(context, K, depth, mesh, std::span(&chosen, 1),
                                              scorer->uses_colour() ? colour : nullptr, Resolution::kFull));
    if (twins) estimate = ResolveTwins(context, *scorer, *full, depth, std::move(estimate), stream_id);
    if (opt.refine.enabled) estimate = RefineEstimate(opt.refine, *full, depth, std::move(estimate));
  }
  if (posterior) MoveSamples(filtered, estimate.T_cam_obj, posterior);
  return estimate;
}

}  // namespace mcpose::engine

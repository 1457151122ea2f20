#include "mcpose/estimator.h"

#include "engine/context.h"
#include "engine/estimate.h"

namespace mcpose {

EngineCounters ObjectEstimate::Totals() const {
  EngineCounters total;
  for (const IterationSummary& it : iterations) total += it.counters;
  return total;
}

Estimator::Estimator(std::unique_ptr<engine::Context> context) : context_(std::move(context)) {}
Estimator::~Estimator() = default;

const EstimatorOptions& Estimator::options() const { return context_->options(); }

void Estimator::PrepareMeshes(std::span<const Mesh* const> meshes) { context_->PrepareMeshes(meshes); }

StatusOr<std::unique_ptr<Estimator>> Estimator::Create(const EstimatorOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) return InvalidArgument("invalid estimator options: " + error);
  MCPOSE_RETURN_IF_ERROR(engine::CheckSimdTarget(options.engine));
  return std::unique_ptr<Estimator>(new Estimator(std::make_unique<engine::Context>(options)));
}

StatusOr<ObjectEstimate> Estimator::Estimate(const Intrinsics& K, const DepthImage& depth, const Mesh& mesh,
                                             std::span<const Detection> boxes, uint64_t stream_id) {
  return Estimate(K, depth, nullptr, mesh, boxes, stream_id);
}

StatusOr<ObjectEstimate> Estimator::Estimate(const Intrinsics& K, const DepthImage& depth, const ColourImage* colour,
                                             const Mesh& mesh, std::span<const Detection> boxes,
                                             uint64_t stream_id) {
  return engine::EstimateObject(*context_, K, depth, colour, mesh, boxes, stream_id);
}

}  // namespace mcpose

#include "mcpose/estimator.h"

#include "engine/context.h"
#include "engine/estimate.h"

namespace mcpose {

EngineCounters& EngineCounters::operator+=(const EngineCounters& o) {
  triangles_full += o.triangles_full;
  triangles_in += o.triangles_in;
  culled_backface += o.culled_backface;
  culled_degenerate += o.culled_degenerate;
  culled_outside_box += o.culled_outside_box;
  culled_near += o.culled_near;
  culled_between_pixels += o.culled_between_pixels;
  triangles_rasterized += o.triangles_rasterized;
  fragments += o.fragments;
  clusters += o.clusters;
  clusters_culled_backface += o.clusters_culled_backface;
  clusters_culled_outside_box += o.clusters_culled_outside_box;
  cdf_draws += o.cdf_draws;
  cdf_reads += o.cdf_reads;
  return *this;
}

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

#include "engine/raster_cores.h"

#include <utility>

#include "core/check.h"

namespace mcpose::engine {

RasterCores::RasterCores(int threads, RasterBackend backend, ThreadScope scope)
    : pool_(threads, std::move(scope)), backend_(backends::MakeBackend(backend)), cores_(static_cast<size_t>(pool_.size())) {}

RasterCores::~RasterCores() = default;

void RasterCores::Score(std::span<const backends::BoxTarget> boxes, const backends::SampleSettings& settings,
                        const filter::ParticleSet& particles, std::span<score::InlierCounts> counts,
                        RasterCounters* stats) {
  MCPOSE_CHECK_EQ(counts.size(), particles.size());
  for (Core& core : cores_) core.stats = RasterCounters{};
  const backends::Backend& backend = *backend_;  // chosen once for the batch
  pool_.ParallelFor(
      static_cast<int64_t>(particles.size()),
      [&](int64_t begin, int64_t end, int worker) {
        Core& core = cores_[static_cast<size_t>(worker)];
        for (int64_t i = begin; i < end; ++i) {
          counts[i] = backend.ScoreSample(boxes[particles.box[i]], particles.R_cam_obj[i].cast<float>(),
                                          particles.t_cam_obj_m[i].cast<float>(), settings, &core.scratch,
                                          &core.stats);
        }
      },
      /*chunks_per_thread=*/16);
  if (stats)
    for (const Core& core : cores_) *stats += core.stats;
}

}  // namespace mcpose::engine

// Render + inlier counting of one iteration (620 samples drawn as the estimator draws them) on
// real YCB-Video frames, at the ground-truth box, over a grid of {object, engine, threads}.
//   build/mcpose_benchmarks --benchmark_filter=ScoreIteration
#include <cstdlib>
#include <map>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>

#include "engine/initialize.h"
#include "engine/raster_cores.h"
#include "mcpose/dataset.h"
#include "mcpose/eval.h"

namespace mcpose {
namespace {

std::string DataDir() {
  if (const char* env = std::getenv("MCPOSE_DATA_DIR"); env && *env) return env;
  return MCPOSE_DEFAULT_DATA_DIR;
}

struct Workload {
  Frame frame;
  Mesh mesh;
  Detection det;
  std::vector<engine::BoxDepth> boxes;
  filter::ParticleSet particles;
};

// One object of one real frame, boxed by its visible mask.
const Workload& GetWorkload(FrameKey key, int obj_id) {
  static std::map<std::pair<FrameKey, int>, std::unique_ptr<Workload>> cache;
  auto& slot = cache[{key, obj_id}];
  if (slot) return *slot;
  auto ds = Dataset::Open(DataDir() + "/ycbv");
  if (!ds.ok()) std::abort();
  auto w = std::make_unique<Workload>();
  w->frame = std::move((*ds)->LoadFrame(key)).value();
  w->mesh = std::move((*ds)->LoadMesh(obj_id)).value();
  for (const GtInstance& gt : w->frame.gt) {
    if (gt.obj_id != obj_id) continue;
    const MaskImage mask = std::move((*ds)->LoadVisibleMask(key, gt)).value();
    w->det = Detection{key.scene_id, key.image_id, obj_id, 1.0};
    MaskBox(mask, &w->det);
  }
  w->boxes.push_back(engine::DistributeDepth(
      w->frame.depth, w->frame.K,
      engine::ClipBox(w->det.x, w->det.y, w->det.w, w->det.h, w->frame.K.width, w->frame.K.height), 1.0,
      InlierMode::k1D));
  EstimatorOptions options;
  engine::InitializeSamples(w->frame.K, w->mesh, std::span(&w->det, 1), w->boxes, options, 1, &w->particles);
  slot = std::move(w);
  return *slot;
}

// Args: object index, engine (0 scalar, 1 fixed), threads.
void BM_ScoreIteration(benchmark::State& state) {
  static const std::pair<FrameKey, int> kObjects[] = {
      {{1, 1}, 2}, {{49, 1}, 3}, {{1, 1}, 5}, {{49, 1}, 9}, {{2, 1}, 10}};
  const auto& [key, obj_id] = kObjects[state.range(0)];
  const Workload& w = GetWorkload(key, obj_id);
  const auto backend = state.range(1) == 0 ? RasterBackend::kScalar : RasterBackend::kFixedPoint;
  engine::RasterCores cores(static_cast<int>(state.range(2)), backend);
  engine::ScoreJob job;
  job.mesh = &w.mesh;
  job.K = w.frame.K;
  job.boxes = w.boxes;
  std::vector<score::InlierCounts> counts(w.particles.size());
  render::RasterStats stats;
  for (auto _ : state) {
    cores.Score(job, w.particles, counts, &stats);
    benchmark::DoNotOptimize(counts.data());
  }
  state.SetLabel("obj " + std::to_string(obj_id) + " " + RasterBackendName(backend));
  state.counters["hypotheses_per_s"] =
      benchmark::Counter(static_cast<double>(w.particles.size()), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["fragments_per_iter"] = static_cast<double>(stats.fragments) / state.iterations();
}

BENCHMARK(BM_ScoreIteration)
    ->ArgNames({"object", "engine", "threads"})
    ->ArgsProduct({{0, 1, 2, 3, 4}, {0, 1}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(1.0);

}  // namespace
}  // namespace mcpose

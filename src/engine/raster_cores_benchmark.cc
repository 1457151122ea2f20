// Micro-benchmarks of the engine's stages on real YCB-Video frames (ground-truth boxes, samples
// drawn as the estimator draws them):
//   BM_ScoreIteration  render + inlier counting of one iteration, grid {object, engine, LOD
//                      (with or without cluster culling),
//                      threads, samples, pixel stride}
//   BM_TriangleSetup   fixed-point triangle setup alone (snap, cull, edge functions, 1/z plane)
//                      over the LOD mesh of every sample, per triangle or batched (SIMD
//                      classification first), grid {object, threads, samples, batched}
//   BM_LodChainBuild   one mesh's LOD chain and culling clusters, grid {object, unbiased}
//   BM_Resample        sort + threshold table + N draws (the paper's resampler), grid {samples}
//   build/mcpose_benchmarks --benchmark_filter=ScoreIteration
#include <algorithm>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>

#include "core/parallel_for.h"
#include "engine/box_scorer.h"
#include "engine/context.h"
#include "engine/initialize.h"
#include "engine/raster_cores.h"
#include "filter/resample.h"
#include "render/lod.h"
#include "render/raster_fixed.h"
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
  std::vector<score::BoxObservation> boxes;
  filter::ParticleSet particles;
  std::unique_ptr<render::LodChain> lod;
  const render::LodLevel* lod_level = nullptr;  // the level a 1-pixel budget picks for this box
};

// One object of one real frame, boxed by its visible mask, scored at a pixel stride.
const Workload& GetWorkload(FrameKey key, int obj_id, int samples, int stride = 1) {
  static std::map<std::tuple<FrameKey, int, int, int>, std::unique_ptr<Workload>> cache;
  auto& slot = cache[{key, obj_id, samples, stride}];
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
  w->boxes.push_back(score::DistributeBox(
      w->frame.depth, w->frame.K,
      engine::ClipBox(w->det.x, w->det.y, w->det.w, w->det.h, w->frame.K.width, w->frame.K.height), 1.0,
      InlierMode::k1D, stride));
  EstimatorOptions options;
  options.samples = samples;
  engine::Context context(options);
  auto scorer = engine::BoxScorer::Create(context, w->frame.K, w->frame.depth, w->mesh, std::span(&w->det, 1));
  if (!scorer.ok()) std::abort();
  engine::InitializeSamples(**scorer, options, 1, &w->particles);
  w->lod = std::make_unique<render::LodChain>(render::LodChain::Build(w->mesh));
  w->lod_level = &w->lod->level(engine::SelectLodLevel(*w->lod, w->frame.K, w->mesh, w->det, w->boxes[0], options));
  slot = std::move(w);
  return *slot;
}

// The paper's five objects in the first real frame that shows each (as `mcpose bench` picks).
constexpr std::pair<FrameKey, int> kObjects[] = {
    {{1, 1}, 2}, {{3, 138}, 4}, {{1, 1}, 5}, {{2, 1}, 9}, {{2, 1}, 10}};

// Args: object index, engine (0 scalar, 1 fixed, 2 simd, 3 float-simd), LOD (0 full mesh, 1 one pixel,
// 2 one pixel with cluster culling, as the estimator runs), threads, samples, pixel stride.
void BM_ScoreIteration(benchmark::State& state) {
  const auto& [key, obj_id] = kObjects[state.range(0)];
  const Workload& w = GetWorkload(key, obj_id, static_cast<int>(state.range(4)), static_cast<int>(state.range(5)));
  const RasterBackend backends[] = {RasterBackend::kScalar, RasterBackend::kFixedPoint, RasterBackend::kSimd,
                                    RasterBackend::kFloatSimd};
  const auto backend = backends[state.range(1)];
  engine::RasterCores cores(static_cast<int>(state.range(3)), backend);
  const backends::BoxTarget box{&w.boxes[0], state.range(2) ? &w.lod_level->mesh : &w.mesh,
                                state.range(2) == 2 ? &w.lod_level->clusters : nullptr};
  backends::SampleSettings settings;
  settings.batched_setup = IsFixedPoint(backend);
  std::vector<score::InlierCounts> counts(w.particles.size());
  RasterCounters stats;
  for (auto _ : state) {
    cores.Score(std::span(&box, 1), settings, w.particles, counts, &stats);
    benchmark::DoNotOptimize(counts.data());
  }
  state.SetLabel("obj " + std::to_string(obj_id) + " " + RasterBackendName(backend) +
                 (state.range(2) == 2 ? " lod+clusters" : state.range(2) ? " lod" : " full") + " stride " + std::to_string(state.range(5)));
  state.counters["hypotheses_per_s"] =
      benchmark::Counter(static_cast<double>(w.particles.size()), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["fragments_per_iter"] = static_cast<double>(stats.fragments) / state.iterations();
}

// Engines x LOD at the paper's 620 samples, 1 and 2 threads, every pixel.
BENCHMARK(BM_ScoreIteration)
    ->ArgNames({"object", "engine", "lod", "threads", "samples", "stride"})
    ->ArgsProduct({{0, 1, 2, 3, 4}, {0, 1, 2, 3}, {0, 1}, {1, 2}, {620}, {1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(0.5);
// The fast engine over {samples, threads, pixel stride}.
BENCHMARK(BM_ScoreIteration)
    ->ArgNames({"object", "engine", "lod", "threads", "samples", "stride"})
    ->ArgsProduct({{2}, {2}, {1}, {1, 2}, {155, 620, 2480}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(0.5);
// The estimator's default engine (simd, LOD with cluster culling, stride 2) for every object.
BENCHMARK(BM_ScoreIteration)
    ->ArgNames({"object", "engine", "lod", "threads", "samples", "stride"})
    ->ArgsProduct({{0, 1, 2, 3, 4}, {2}, {2}, {1, 2}, {620}, {2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(0.5);

// Triangle setup alone: every triangle of the 1-pixel LOD mesh of every sample (vertices
// projected beforehand), SetupFixedTriangle and nothing else. Args: object index, threads,
// samples.
void BM_TriangleSetup(benchmark::State& state) {
  const auto& [key, obj_id] = kObjects[state.range(0)];
  const Workload& w = GetWorkload(key, obj_id, static_cast<int>(state.range(2)));
  const Mesh& mesh = w.lod_level->mesh;
  const render::RasterParams p = score::BoxRasterParams(w.boxes[0], true);
  const size_t n = w.particles.size(), nv = mesh.vertices_m.size();
  std::vector<render::ScreenVertex> projected(n * nv);
  for (size_t i = 0; i < n; ++i)
    render::ProjectVertices(mesh.vertices_m, w.particles.R_cam_obj[i].cast<float>(),
                            w.particles.t_cam_obj_m[i].cast<float>(), p,
                            std::span(projected.data() + i * nv, nv));
  ThreadPool pool(static_cast<int>(state.range(1)));
  std::vector<int64_t> ready(static_cast<size_t>(pool.size()));
  const bool batched = state.range(3) != 0;
  std::vector<render::SnappedVertices> snapped(static_cast<size_t>(pool.size()));
  for (auto _ : state) {
    pool.ParallelFor(static_cast<int64_t>(n), [&](int64_t b, int64_t e, int worker) {
      render::FixedTriangle ft;
      render::SnappedVertices& sv = snapped[static_cast<size_t>(worker)];
      RasterCounters stats;
      int64_t k = 0;
      for (int64_t i = b; i < e; ++i) {
        const render::ScreenVertex* v = projected.data() + i * nv;
        if (!batched) {
          for (const auto& t : mesh.triangles)
            k += render::SetupFixedTriangle(v[t[0]], v[t[1]], v[t[2]], p, &ft) == render::TriangleSetup::kReady;
          continue;
        }
        // Batched, as the engine: snap once, classify a vector at a time, set up the survivors
        // a vector at a time, the rest (culls found late, deferred vertices) one by one.
        render::SnapVertices(std::span(v, nv), p, &sv);
        const size_t kept = render::ClassifyTriangles(sv, mesh.triangles, p, &stats, &sv.survivors);
        sv.setups.resize(std::max(sv.setups.size(), kept)), sv.ready.resize(std::max(sv.ready.size(), kept));
        render::SetupSurvivors(sv, std::span(v, nv), mesh.triangles, p, std::span(sv.survivors.data(), kept),
                               sv.setups.data(), sv.ready.data());
        for (size_t j = 0; j < kept; ++j) {
          k += sv.ready[j] ||
               render::SetupBatchedTriangle(std::span(v, nv), sv.packed.data(), mesh.triangles[sv.survivors[j]], p,
                                            &ft) == render::TriangleSetup::kReady;
        }
      }
      ready[static_cast<size_t>(worker)] += k;
      benchmark::DoNotOptimize(ft);
    });
  }
  int64_t total_ready = 0;
  for (int64_t r : ready) total_ready += r;
  state.SetLabel("obj " + std::to_string(obj_id) + ", " + std::to_string(mesh.triangles.size()) + " triangles" +
                 (batched ? ", batched" : ""));
  state.counters["triangles_per_s"] = benchmark::Counter(static_cast<double>(n * mesh.triangles.size()),
                                                         benchmark::Counter::kIsIterationInvariantRate);
  state.counters["ready_share"] =
      static_cast<double>(total_ready) / (static_cast<double>(state.iterations()) * n * mesh.triangles.size());
}
BENCHMARK(BM_TriangleSetup)
    ->ArgNames({"object", "threads", "samples", "batched"})
    ->ArgsProduct({{0, 1, 2, 3, 4}, {1, 2}, {620}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(0.5);
BENCHMARK(BM_TriangleSetup)
    ->ArgNames({"object", "threads", "samples", "batched"})
    ->ArgsProduct({{2}, {1, 2}, {155, 2480}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(0.5);

// Building one mesh's LOD chain and its clusters (once per mesh and process; PrepareMeshes runs
// one mesh per raster core). Args: object index, unbiased vertices (1, the default) or
// meshoptimizer's (0).
void BM_LodChainBuild(benchmark::State& state) {
  const auto& [key, obj_id] = kObjects[state.range(0)];
  const Workload& w = GetWorkload(key, obj_id, 1);
  const render::LodVertices vertices = state.range(1) ? render::LodVertices::kUnbiased : render::LodVertices::kKept;
  int levels = 0;
  for (auto _ : state) levels = render::LodChain::Build(w.mesh, vertices).num_levels();
  state.SetLabel(std::to_string(obj_id) + ", " + std::to_string(levels) + " levels");
}
BENCHMARK(BM_LodChainBuild)
    ->ArgNames({"object", "unbiased"})
    ->ArgsProduct({{0, 1, 2, 3, 4}, {0, 1}})
    ->Unit(benchmark::kMillisecond);

// Sort + table + one draw per sample, on weights of the shape the filter produces (a few
// heavy samples over a long light tail). Args: samples, table size.
void BM_Resample(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  std::vector<double> weights(static_cast<size_t>(n));
  uint64_t x = 88172645463325252ull;
  for (double& w : weights) {
    x ^= x << 13, x ^= x >> 7, x ^= x << 17;
    const double u = static_cast<double>(x >> 11) * 0x1.0p-53;
    w = 0.3 + 0.6 * u * u * u;
  }
  filter::CdfSampler sampler;
  int64_t reads = 0, draws = 0;
  for (auto _ : state) {
    sampler.Build(weights, 1.0, static_cast<int>(state.range(1)));
    for (int i = 0; i < n; ++i) benchmark::DoNotOptimize(sampler.Draw((i + 0.5) / n, &reads));
    draws += n;
  }
  state.counters["reads_per_draw"] = static_cast<double>(reads) / static_cast<double>(draws);
}
BENCHMARK(BM_Resample)->ArgNames({"samples", "table"})->ArgsProduct({{155, 620, 2480}, {1, 64}})->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace mcpose

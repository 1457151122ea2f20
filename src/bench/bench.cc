#include "mcpose/bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <thread>

#include "baselines/depth_baseline.h"
#include "bench/naive_cdf.h"
#include "core/parallel_for.h"
#include "core/rng.h"
#include "engine/box_scorer.h"
#include "engine/context.h"
#include "engine/filter_loop.h"
#include "engine/initialize.h"
#include "mcpose/run.h"
#include "mcpose/eval.h"
#include "hw/weight_merger.h"
#include "score/inlier.h"

namespace mcpose::bench {

namespace {

using Clock = std::chrono::steady_clock;

// Substream of the naive resampler's draws (bench only).
constexpr uint64_t kNaiveStream = 0x4A17E;

double MsSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

struct Stats3 {
  double median = 0, min = 0, max = 0;
};

Stats3 Summarize(std::vector<double> v) {
  Stats3 s;
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  s.median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  s.min = v.front(), s.max = v.back();
  return s;
}

// The first frame (sorted) in which obj_id is visible, with its tight visible-mask box.
Status FindObject(const Dataset& ds, int obj_id, Frame* frame, Detection* box) {
  for (const FrameKey& key : ds.Frames()) {
    MCPOSE_ASSIGN_OR_RETURN(Frame f, ds.LoadFrame(key));
    for (const GtInstance& gt : f.gt) {
      if (gt.obj_id != obj_id) continue;
      MCPOSE_ASSIGN_OR_RETURN(MaskImage mask, ds.LoadVisibleMask(key, gt));
      Detection d{key.scene_id, key.image_id, obj_id, 1.0};
      if (MaskBox(mask, &d) == 0) continue;
      *frame = std::move(f);
      *box = d;
      return Status::Ok();
    }
  }
  return NotFound("obj_id " + std::to_string(obj_id) + " (" + ds.ObjectName(obj_id) +
                  ") is visible in no frame of " + ds.root());
}

}  // namespace

std::string MachineDescriptionFrom(std::istream& cpuinfo, int hardware_threads) {
  std::string line, model, family, model_number;
  int cpus = 0;
  // The value after "key<tabs>: " of a /proc/cpuinfo line that starts with key and a tab.
  auto value = [&line](const char* key, std::string* out) {
    const std::string k = std::string(key) + "\t";
    if (out->empty() && line.rfind(k, 0) == 0 && line.find(':') != std::string::npos)
      *out = line.substr(std::min(line.size(), line.find(':') + 2));
  };
  while (std::getline(cpuinfo, line)) {
    value("model name", &model);
    value("cpu family", &family);
    value("model", &model_number);  // "model\t\t: 1", not "model name"
    if (line.rfind("processor", 0) == 0) ++cpus;
  }
  if (model.empty()) model = "unknown CPU";
  // Virtual machines often report only the brand ("AMD EPYC"); family and model tell the
  // generations apart (AMD family 25: model 1 Zen 3, model 17 Zen 4), which ran mcpose 2x
  // apart in speed.
  if (!family.empty() && !model_number.empty()) model += " (family " + family + " model " + model_number + ")";
  return model + ", " + std::to_string(cpus ? cpus : hardware_threads) + " logical CPUs";
}

std::string MachineDescription() {
  std::ifstream in("/proc/cpuinfo");
  return MachineDescriptionFrom(in, static_cast<int>(std::thread::hardware_concurrency()));
}

StatusOr<std::vector<BenchObject>> RunBench(const Dataset& ds, const BenchOptions& options,
                                            const BenchProgressFn& progress) {
  std::vector<int> ids = options.obj_ids;
  if (ids.empty()) ids = {2, 4, 5, 9, 10};
  const std::vector<int> known = ds.ObjectIds();
  for (size_t i = 0; i < ids.size(); ++i) {
    if (!std::binary_search(known.begin(), known.end(), ids[i]))
      return InvalidArgument("--objects: unknown obj_id " + std::to_string(ids[i]) + " in " + ds.root());
    if (std::find(ids.begin(), ids.begin() + static_cast<std::ptrdiff_t>(i), ids[i]) != ids.begin() + i)
      return InvalidArgument("--objects: obj_id " + std::to_string(ids[i]) + " is listed twice");
  }
  if (options.iterations < 1 || options.iterations > limits::kMaxIterations)
    return InvalidArgument("--iterations must lie in [1, " + std::to_string(limits::kMaxIterations) + "]");
  if (options.render_repeats < 1 || options.render_repeats > 1000)
    return InvalidArgument("--repeats must lie in [1, 1000]");
  for (const auto& b : options.baselines)
    if (b != "embree" && b != "osmesa")
      return InvalidArgument("--baselines: unknown baseline '" + b + "' (expected embree, osmesa)");

  EstimatorOptions eo = options.estimator;
  eo.tau = std::numeric_limits<double>::max();  // weights are <= 1: never stops early
  eo.max_iterations = options.iterations;
  std::string error;
  if (!eo.IsValid(&error)) return InvalidArgument("invalid options: " + error);
  // The baselines count 1-D inliers, and the boxes below are distributed for that test.
  if (eo.weight.inlier != InlierMode::k1D)
    return InvalidArgument("invalid options: the benchmark times the 1-D inlier test (inlier_mode 1d)");
  engine::Context context(eo);

  std::vector<BenchObject> out;
  for (int obj_id : ids) {
    BenchObject r;
    r.obj_id = obj_id;
    r.name = ds.ObjectName(obj_id);
    Frame frame;
    MCPOSE_RETURN_IF_ERROR(FindObject(ds, obj_id, &frame, &r.box));
    r.frame = frame.key;
    MCPOSE_ASSIGN_OR_RETURN(Mesh mesh, ds.LoadMesh(obj_id));
    const Intrinsics& K = frame.K;
    r.samples = eo.samples;
    r.threads = context.cores().threads();
    // The depth-only scorer (the colour one, below, where the model has colour).
    MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<engine::BoxScorer> scorer,
                            engine::BoxScorer::Create(context, K, frame.depth, mesh, std::span(&r.box, 1)));
    const uint64_t stream_id = GroupStreamId(r.frame.scene_id, r.frame.image_id, obj_id);

    // ---- Full iterations: the estimator's filter loop ------------------------------------
    // The naive resampler's reads for the same number of draws on each resampled generation.
    int64_t naive_reads = 0;
    NaiveCdf naive;
    filter::ParticleSet last_generation;  // for the colour comparison below
    const auto observer = [&](int iter, const filter::ParticleSet& weighted) {
      if (iter + 1 == eo.max_iterations) {  // the last generation is not resampled
        last_generation = weighted;
        return;
      }
      // As many draws as the loop makes: a generation of eo.samples less its elite.
      naive.Build(weighted.weight, eo.resample.keep_top_fraction);
      for (int i = engine::EliteCount(eo, eo.samples); i < eo.samples; ++i)
        naive_reads += naive.Reads(Rng(eo.seed, stream_id, kNaiveStream + static_cast<uint64_t>(iter), static_cast<uint64_t>(i)).Uniform());
    };
    const ObjectEstimate e = engine::RunFilter(*scorer, eo, context.pool(), stream_id, observer);
    r.per_iteration = e.iterations;
    r.counters = e.Totals();
    std::vector<double> iteration_ms, score_ms;
    for (const IterationSummary& it : e.iterations) iteration_ms.push_back(it.iteration_ms), score_ms.push_back(it.score_ms);
    const int iterations = static_cast<int>(e.iterations.size());
    const Stats3 full = Summarize(iteration_ms), score = Summarize(score_ms);
    r.full_iteration_ms_median = full.median, r.full_iteration_ms_min = full.min, r.full_iteration_ms_max = full.max;
    r.render_inlier_ms_median = score.median, r.render_inlier_ms_min = score.min, r.render_inlier_ms_max = score.max;
    r.hypotheses_per_s = full.median > 0 ? 1000.0 * eo.samples / full.median : 0;
    // The same with the colour term, when the model has colour.
    if (eo.appearance.enabled && !mesh.appearance.empty()) {
      MCPOSE_ASSIGN_OR_RETURN(ColourImage colour, ds.LoadColour(frame));
      MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<engine::BoxScorer> with_colour,
                              engine::BoxScorer::Create(context, K, frame.depth, mesh, std::span(&r.box, 1), &colour));
      const ObjectEstimate c = engine::RunFilter(*with_colour, eo, context.pool(), stream_id);
      std::vector<double> c_iteration_ms, c_score_ms;
      for (const IterationSummary& it : c.iterations) c_iteration_ms.push_back(it.iteration_ms), c_score_ms.push_back(it.score_ms);
      r.colour = true;
      r.colour_full_iteration_ms_median = Summarize(c_iteration_ms).median;
      r.colour_render_inlier_ms_median = Summarize(c_score_ms).median;
      r.colour_ratio = full.median > 0 ? r.colour_full_iteration_ms_median / full.median : 0;
      // The same hypotheses (the depth-only run's last generation, on the object), scored with
      // and without colour in alternating rounds; the rest of an iteration (weights,
      // resampling, diffusion) is the depth-only run's.
      std::vector<score::InlierCounts> counts(last_generation.size());
      std::vector<double> depth_ms, colour_ms;
      EngineCounters ignored;
      for (int k = 0; k < std::max(3, options.render_repeats); ++k) {
        auto t0 = Clock::now();
        scorer->Count(last_generation, counts, &ignored);
        depth_ms.push_back(MsSince(t0));
        t0 = Clock::now();
        with_colour->Count(last_generation, counts, &ignored);
        colour_ms.push_back(MsSince(t0));
      }
      const double rest = std::max(0.0, full.median - score.median);
      r.colour_same_render_inlier_ms = Summarize(colour_ms).median;
      r.depth_same_render_inlier_ms = Summarize(depth_ms).median;
      r.colour_same_ratio = (r.colour_same_render_inlier_ms + rest) / (r.depth_same_render_inlier_ms + rest);
    }
    r.triangles_full = static_cast<int>(mesh.triangles.size());
    r.triangles_lod = e.box_triangles[0];
    const double renders = static_cast<double>(eo.samples) * iterations;
    r.triangles_after_cull = r.counters.triangles_rasterized / renders;
    r.fragments_per_iteration = static_cast<double>(r.counters.fragments) / iterations;
    const EngineCounters& c = r.counters;
    r.cdf_reads_per_draw = c.cdf_draws ? static_cast<double>(c.cdf_reads) / c.cdf_draws : 0;
    r.cdf_reads_per_draw_naive = c.cdf_draws ? static_cast<double>(naive_reads) / c.cdf_draws : 0;
    r.depth_bytes_read = e.depth_pixels_read * int64_t{sizeof(float)};
    r.depth_bytes_read_naive = scorer->box_observation(0).rect.area() * int64_t{sizeof(float)} * eo.samples * iterations;

    // ---- Render + inlier on the initial hypotheses: mcpose and the baselines -------------
    filter::ParticleSet particles;
    engine::InitializeSamples(*scorer, eo, stream_id, &particles);
    const render::LodLevel* level = scorer->box_level(0);
    const Mesh& render_mesh = scorer->box_mesh(0);
    r.lod_deviation_mm = level ? 1000.0 * level->error_m : 0.0;
    r.lod_meshopt_error_mm = level ? 1000.0 * level->meshopt_error_m : 0.0;
    const score::BoxObservation& box = scorer->box_observation(0);
    std::vector<score::InlierCounts> counts(particles.size());
    const float eps_m = static_cast<float>(eo.weight.eps_m);

    // The box's sample grid (every pixel at stride 1): the baselines cast the same rays.
    const render::RasterParams params = score::BoxRasterParams(box, eo.engine.backface_culling);
    struct Baseline {
      std::unique_ptr<baselines::DepthBaseline> renderer;
      std::vector<score::InlierCounts> counts;
      std::vector<std::vector<float>> zbuf;  // per worker
      std::vector<double> ms;                // per timed round
    };
    std::vector<Baseline> bases;
    for (const std::string& name : options.baselines) {
      Baseline b;
      MCPOSE_ASSIGN_OR_RETURN(b.renderer, baselines::CreateDepthBaseline(name, render_mesh, K.width, K.height));
      b.counts.resize(particles.size());
      const int workers = b.renderer->thread_safe() ? context.cores().threads() : 1;
      b.zbuf.assign(static_cast<size_t>(workers), std::vector<float>(static_cast<size_t>(params.box.area())));
      bases.push_back(std::move(b));
    }
    // Render + inlier of every hypothesis by one baseline, on the raster cores' threads when
    // the baseline is thread-safe. Returns the wall time in ms.
    const auto run_baseline = [&](Baseline& b) {
      auto render_one = [&](int64_t i, int worker) {
        std::vector<float>& z = b.zbuf[static_cast<size_t>(worker)];
        b.renderer->Render(particles.R_cam_obj[i].cast<float>(), particles.t_cam_obj_m[i].cast<float>(), params,
                           z.data());
        b.counts[i] = score::CountInliers1D(z, box.observed, eps_m);
      };
      const auto t0 = Clock::now();
      if (b.zbuf.size() > 1) {
        context.pool().ParallelFor(static_cast<int64_t>(particles.size()), [&](int64_t begin, int64_t end, int w) {
          for (int64_t i = begin; i < end; ++i) render_one(i, w);
        });
      } else {
        for (int64_t i = 0; i < static_cast<int64_t>(particles.size()); ++i) render_one(i, 0);
      }
      return MsSince(t0);
    };
    const auto run_mcpose = [&] {
      const auto t0 = Clock::now();
      EngineCounters ignored;
      scorer->Count(particles, counts, &ignored);
      return MsSince(t0);
    };
    // One untimed run of each first (caches, thread wake-up, the baselines' first-use costs).
    // Then `render_repeats` rounds, each timing every baseline once and mcpose about as long
    // (`runs` times, mcpose's warm-up time into the fastest baseline's): both medians sample
    // the same stretches of a shared, noisy machine.
    const double warm_ms = run_mcpose();
    double fastest_baseline_ms = 0;
    for (size_t j = 0; j < bases.size(); ++j) {
      const double ms = run_baseline(bases[j]);
      fastest_baseline_ms = j == 0 ? ms : std::min(fastest_baseline_ms, ms);
    }
    const int runs = bases.empty() || !(warm_ms > 0)
                         ? 1
                         : static_cast<int>(std::clamp(std::lround(fastest_baseline_ms / warm_ms), 1L, 32L));
    std::vector<double> times;
    for (int k = 0; k < options.render_repeats; ++k) {
      for (int j = 0; j < runs; ++j) times.push_back(run_mcpose());
      for (Baseline& b : bases) b.ms.push_back(run_baseline(b));
    }
    r.mcpose_render_inlier_initial_ms = Summarize(times).median;
    r.mcpose_render_inlier_initial_runs = static_cast<int>(times.size());
    for (const auto& cnt : counts) r.mcpose_inliers_total += cnt.inliers;

    for (size_t j = 0; j < bases.size(); ++j) {
      const Baseline& b = bases[j];
      BaselineResult br;
      br.name = options.baselines[j];
      br.render_inlier_ms_median = Summarize(b.ms).median;
      br.speedup = r.mcpose_render_inlier_initial_ms > 0 ? br.render_inlier_ms_median / r.mcpose_render_inlier_initial_ms : 0;
      double abs_diff = 0;
      for (size_t i = 0; i < b.counts.size(); ++i) {
        br.inliers_total += b.counts[i].inliers;
        abs_diff += std::abs(b.counts[i].inliers - counts[i].inliers) / std::max(1.0, double(counts[i].rendered));
      }
      br.inliers_rel_diff = r.mcpose_inliers_total
                                ? std::abs(double(br.inliers_total - r.mcpose_inliers_total)) / r.mcpose_inliers_total
                                : 0;
      br.inliers_mean_abs_diff = b.counts.empty() ? 0 : abs_diff / b.counts.size();
      r.baselines.push_back(br);
    }
    if (progress) progress(r);
    out.push_back(std::move(r));
  }
  return out;
}

StatusOr<int64_t> WriteHardwareWorkload(const Dataset& ds, const BenchOptions& options, std::ostream& out) {
  std::vector<int> ids = options.obj_ids;
  if (ids.empty()) ids = {2, 4, 5, 9, 10};
  EstimatorOptions eo = options.estimator;
  eo.engine.backend = RasterBackend::kHardware;
  eo.engine.DropUnusableFeatures();
  eo.weight.inlier = InlierMode::k1D;
  std::string error;
  if (!eo.IsValid(&error)) return InvalidArgument("invalid options: " + error);
  engine::Context context(eo);
  int64_t written = 0;
  out << "# mcpose hardware workload v3: per object its box's observed depth, weight, mesh and samples\n";
  for (int obj_id : ids) {
    Frame frame;
    Detection box;
    MCPOSE_RETURN_IF_ERROR(FindObject(ds, obj_id, &frame, &box));
    MCPOSE_ASSIGN_OR_RETURN(Mesh mesh, ds.LoadMesh(obj_id));
    MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<engine::BoxScorer> scorer,
                            engine::BoxScorer::Create(context, frame.K, frame.depth, mesh, std::span(&box, 1)));
    const uint64_t stream_id = GroupStreamId(frame.key.scene_id, frame.key.image_id, obj_id);
    filter::ParticleSet particles;
    engine::InitializeSamples(*scorer, eo, stream_id, &particles);
    std::vector<score::InlierCounts> counts(particles.size());
    EngineCounters ignored;
    scorer->Count(particles, counts, &ignored);
    // The core's inputs, as the hw backend forms them.
    const score::BoxObservation& obs = scorer->box_observation(0);
    const hw::Camera c = score::BoxHardwareCamera(obs);
    const Mesh& level = scorer->box_mesh(0);
    std::vector<hw::ModelVertex> model;
    if (!hw::QuantizeModel(level.vertices_m, &model)) return Internal("mesh out of the hardware's range");
    out << "object " << obj_id << ' ' << ds.ObjectName(obj_id) << " frame " << frame.key.scene_id << ' '
        << frame.key.image_id << '\n';
    out << "camera " << c.fx << ' ' << c.fy << ' ' << c.cx << ' ' << c.cy << ' ' << c.z_near << ' ' << c.width << ' '
        << c.height << ' ' << (eo.engine.backface_culling ? 1 : 0) << '\n';
    const hw::WeightCoefficients w =
        hw::QuantizeWeight(eo.weight.a, eo.weight.b, eo.weight.c, box.score, eo.weight.occlusion_aware);
    out << "weight " << w.a << ' ' << w.b << ' ' << w.c << ' ' << w.score << ' ' << (w.occlusion_aware ? 1 : 0) << '\n';
    // The depth distributor's input: the box's depth in depth units (its bounds are
    // hw::InlierBounds of each, as obs.depth_bounds holds them).
    const std::vector<int32_t> depth = hw::ObservedDepthUnits(obs.observed);
    out << "depth " << depth.size() << ' ' << hw::EpsUnits(static_cast<float>(eo.weight.eps_m)) << '\n';
    for (int32_t d : depth) out << d << '\n';
    out << "vertices " << model.size() << '\n';
    for (const hw::ModelVertex& v : model) out << v[0] << ' ' << v[1] << ' ' << v[2] << '\n';
    out << "triangles " << level.triangles.size() << '\n';
    for (const auto& t : level.triangles) out << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
    out << "samples " << particles.size() << '\n';
    for (size_t i = 0; i < particles.size(); ++i) {
      const hw::Pose pose = hw::QuantizePose(particles.R_cam_obj[i].cast<float>(), particles.t_cam_obj_m[i].cast<float>());
      for (int32_t r : pose.R) out << r << ' ';
      for (int32_t t : pose.t) out << t << ' ';
      out << counts[i].inliers << ' ' << counts[i].rendered << ' ' << counts[i].occluded << '\n';
    }
    written += static_cast<int64_t>(particles.size());
  }
  out << "end\n";
  if (!out) return Internal("cannot write the workload");
  return written;
}

}  // namespace mcpose::bench

#include <cstdio>
#include <memory>
#include <sstream>

#include <nlohmann/json.hpp>

#include "mcpose/bench.h"
#include "cli/common.h"
#include "mcpose/io_util.h"
#include "commands.h"
#include "mcpose/options_json.h"
#include "mcpose/simd.h"
#include "mcpose/dataset.h"

namespace mcpose::cli {

namespace {

struct BenchArgs {
  std::string dataset, split = "test", models, json, baselines;
  std::vector<int> objects;
  bench::BenchOptions options;
  EstimatorFlags flags;
};

nlohmann::json ObjectJson(const bench::BenchObject& r) {
  nlohmann::json j = {
      {"obj_id", r.obj_id},
      {"name", r.name},
      {"scene_id", r.frame.scene_id},
      {"im_id", r.frame.image_id},
      {"bbox", {r.box.x, r.box.y, r.box.w, r.box.h}},
      {"samples", r.samples},
      {"threads", r.threads},
      {"iterations", r.per_iteration.size()},
      {"triangles_full", r.triangles_full},
      {"triangles_lod", r.triangles_lod},
      {"lod_deviation_mm", r.lod_deviation_mm},
      {"lod_meshopt_error_mm", r.lod_meshopt_error_mm},
      {"triangles_after_cull", r.triangles_after_cull},
      {"fragments_per_iteration", r.fragments_per_iteration},
      {"render_inlier_ms_median", r.render_inlier_ms_median},
      {"render_inlier_ms_min", r.render_inlier_ms_min},
      {"render_inlier_ms_max", r.render_inlier_ms_max},
      {"full_iteration_ms_median", r.full_iteration_ms_median},
      {"full_iteration_ms_min", r.full_iteration_ms_min},
      {"full_iteration_ms_max", r.full_iteration_ms_max},
      {"hypotheses_per_s", r.hypotheses_per_s},
      {"initial_render_inlier_ms_median", r.mcpose_render_inlier_initial_ms},
      {"initial_render_inlier_runs", r.mcpose_render_inlier_initial_runs},
      {"initial_inliers_total", r.mcpose_inliers_total},
      {"cdf_reads_per_draw", r.cdf_reads_per_draw},
      {"cdf_reads_per_draw_naive", r.cdf_reads_per_draw_naive},
      {"depth_bytes_read", r.depth_bytes_read},
      {"depth_bytes_read_naive", r.depth_bytes_read_naive},
      {"counters", io::CountersToJson(r.counters)},
      {"colour", r.colour},
      {"colour_full_iteration_ms_median", r.colour_full_iteration_ms_median},
      {"colour_render_inlier_ms_median", r.colour_render_inlier_ms_median},
      {"colour_ratio", r.colour_ratio},
      {"depth_same_render_inlier_ms", r.depth_same_render_inlier_ms},
      {"colour_same_render_inlier_ms", r.colour_same_render_inlier_ms},
      {"colour_same_ratio", r.colour_same_ratio},
  };
  nlohmann::json full_ms = nlohmann::json::array(), score_ms = nlohmann::json::array(),
                 fragments = nlohmann::json::array(), mean_weight = nlohmann::json::array();
  for (const IterationSummary& it : r.per_iteration) {
    full_ms.push_back(it.iteration_ms), score_ms.push_back(it.score_ms);
    fragments.push_back(it.counters.fragments), mean_weight.push_back(it.mean_weight);
  }
  j["per_iteration"] = {
      {"full_ms", full_ms}, {"render_inlier_ms", score_ms}, {"fragments", fragments}, {"mean_weight", mean_weight}};
  // The flat fields; null when the baseline was not run.
  j["embree_ms_median"] = nullptr, j["speedup_embree"] = nullptr;
  j["osmesa_ms_median"] = nullptr, j["speedup_osmesa"] = nullptr;
  nlohmann::json bl = nlohmann::json::array();
  for (const auto& b : r.baselines) {
    j[b.name + "_ms_median"] = b.render_inlier_ms_median;
    j["speedup_" + b.name] = b.speedup;
    bl.push_back({{"name", b.name},
                  {"render_inlier_ms_median", b.render_inlier_ms_median},
                  {"speedup", b.speedup},
                  {"inliers_total", b.inliers_total},
                  {"inliers_rel_diff", b.inliers_rel_diff},
                  {"inliers_mean_abs_diff", b.inliers_mean_abs_diff}});
  }
  j["baselines"] = bl;
  return j;
}

Status RunBenchCommand(BenchArgs& a) {
  MCPOSE_RETURN_IF_ERROR(a.flags.Finish());
  a.options.estimator = a.flags.options;
  const EstimatorOptions& o = a.options.estimator;
  a.options.obj_ids = a.objects;
  a.options.baselines.clear();
  std::stringstream ss(a.baselines);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) a.options.baselines.push_back(item);
  if (!a.json.empty()) MCPOSE_RETURN_IF_ERROR(CheckWritable(a.json));
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<Dataset> dataset, Dataset::Open(a.dataset, a.split, a.models));
  MCPOSE_RETURN_IF_ERROR(CheckOutputsOutsideDataset(*dataset, {{"--json", a.json}}));

  const std::string machine = bench::MachineDescription();
  // The header comes with the first object, so that input RunBench rejects before timing
  // anything (an unknown obj_id or baseline) leaves only the error.
  bool header_printed = false;
  auto progress = [&](const bench::BenchObject& r) {
    if (!header_printed) {
      header_printed = true;
      std::printf("machine: %s\nengine %s (SIMD target %s), LOD %.2f px, pixel stride %d, %d samples, "
                  "%d iterations, threads %d\n",
                  machine.c_str(), RasterBackendName(o.engine.backend), render::DispatchedSimdTarget(o.engine.simd_target).c_str(),
                  o.engine.lod_error_px, o.engine.pixel_stride, o.samples, a.options.iterations, o.engine.threads);
      std::printf("%-20s %6s %5s %8s %9s | %8s %17s | %8s %17s %9s | %s\n", "object", "tris", "lod", "culled",
                  "frags/it", "r+i ms", "(min-max)", "full ms", "(min-max)", "hyp/s",
                  "baselines (ms, x, inlier diff)");
    }
    std::string base;
    for (const auto& b : r.baselines) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "%s %.1f ms %.1fx %.2f%%  ", b.name.c_str(), b.render_inlier_ms_median,
                    b.speedup, 100 * b.inliers_rel_diff);
      base += buf;
    }
    std::printf("%-20s %6d %5d %8.0f %9.0f | %8.2f (%6.2f-%7.2f) | %8.2f (%6.2f-%7.2f) %9.0f | %s\n",
                r.name.c_str(), r.triangles_full, r.triangles_lod, r.triangles_after_cull,
                r.fragments_per_iteration, r.render_inlier_ms_median, r.render_inlier_ms_min,
                r.render_inlier_ms_max, r.full_iteration_ms_median, r.full_iteration_ms_min,
                r.full_iteration_ms_max, r.hypotheses_per_s, base.c_str());
    std::printf("  %s scene %d image %d; LOD deviation %.2f mm (meshoptimizer's figure %.2f); "
                "cdf reads/draw %.2f (naive %.1f); depth bytes %lld (naive %lld); initial r+i %.2f ms (%d runs)\n",
                r.name.c_str(), r.frame.scene_id, r.frame.image_id, r.lod_deviation_mm, r.lod_meshopt_error_mm,
                r.cdf_reads_per_draw, r.cdf_reads_per_draw_naive,
                static_cast<long long>(r.depth_bytes_read), static_cast<long long>(r.depth_bytes_read_naive),
                r.mcpose_render_inlier_initial_ms, r.mcpose_render_inlier_initial_runs);
    if (r.colour) {
      std::printf("  %s with colour: full %.2f ms (%.2fx depth only), r+i %.2f ms; on the same hypotheses r+i %.2f "
                  "ms against %.2f, full %.2fx\n",
                  r.name.c_str(), r.colour_full_iteration_ms_median, r.colour_ratio, r.colour_render_inlier_ms_median,
                  r.colour_same_render_inlier_ms, r.depth_same_render_inlier_ms, r.colour_same_ratio);
    }
    std::fflush(stdout);
  };
  MCPOSE_ASSIGN_OR_RETURN(std::vector<bench::BenchObject> objects, bench::RunBench(*dataset, a.options, progress));

  if (!a.json.empty()) {
    nlohmann::json arr = nlohmann::json::array();
    for (const auto& r : objects) arr.push_back(ObjectJson(r));
    nlohmann::json options = io::OptionsToJson(o);
    options["engine"]["simd_target"] = render::DispatchedSimdTarget(o.engine.simd_target);
    options["iterations"] = a.options.iterations;
    options["render_repeats"] = a.options.render_repeats;
    nlohmann::json doc = {{"machine",
                           {{"cpu", machine},
                            {"simd_targets", render::SimdTargetsAvailable()},
                            {"threads", objects.empty() ? o.engine.threads : objects[0].threads}}},
                          {"options", options},
                          {"objects", arr}};
    MCPOSE_RETURN_IF_ERROR(io::WriteFileAtomic(a.json, doc.dump(1) + "\n"));
  }
  return Status::Ok();
}

}  // namespace

void AddBenchCommand(CLI::App& app, Status* status) {
  auto args = std::make_shared<BenchArgs>();
  CLI::App* cmd = app.add_subcommand(
      "bench", "Time one Monte-Carlo iteration per object on real frames (ground-truth boxes), with baselines");
  cmd->add_option("--dataset", args->dataset, "Dataset root (YCB-Video native or BOP layout)")->required();
  cmd->add_option("--split", args->split, "BOP split folder")->capture_default_str();
  cmd->add_option("--models", args->models, "Models folder to read meshes (and their colour) from");
  cmd->add_option("--objects", args->objects, "obj_ids (default: the paper's five: 2 4 5 9 10)")->delimiter(',');
  cmd->add_option("--iterations", args->options.iterations, "Full iterations timed per object")->capture_default_str();
  cmd->add_option("--repeats", args->options.render_repeats,
                  "Rounds of render + inlier on the initial hypotheses: each times every baseline once and mcpose "
                  "about as long")->capture_default_str();
  AddEstimatorFlags(cmd, kSamplingOptions | kWeightOptions | kSearchOptions | kEngineOptions | kAppearanceOptions, &args->flags);
  cmd->add_option("--baselines", args->baselines, "Comma-separated: embree,osmesa (same hypotheses, same boxes)");
  cmd->add_option("--json", args->json, "Write {machine, options, objects: [...]} here");
  cmd->callback([args, status] { *status = RunBenchCommand(*args); });
}

}  // namespace mcpose::cli

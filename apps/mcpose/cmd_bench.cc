#include <cstdio>
#include <memory>
#include <sstream>

#include <nlohmann/json.hpp>

#include "bench/bench.h"
#include "commands.h"
#include "mcpose/dataset.h"

namespace mcpose::cli {

namespace {

struct BenchArgs {
  std::string dataset, split = "test", json, engine = "simd", baselines, simd_target;
  std::vector<int> objects;
  bench::BenchOptions options;
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
      {"iterations", r.iterations},
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
      {"counters", CountersJson(r.counters)},
      {"per_iteration",
       {{"full_ms", r.iteration_ms},
        {"render_inlier_ms", r.score_ms},
        {"fragments", r.fragments_per_iteration_series},
        {"depth_bytes_read", r.depth_bytes_per_iteration},
        {"mean_weight", r.mean_weight_history}}},
  };
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
  EstimatorOptions& o = a.options.estimator;
  if (!ParseRasterBackend(a.engine, &o.backend))
    return InvalidArgument(std::string("--engine must be ") + kRasterBackendChoices + ", got '" + a.engine + "'");
  MCPOSE_RETURN_IF_ERROR(ApplySimdTarget(a.simd_target));
  a.options.obj_ids = a.objects;
  a.options.baselines.clear();
  std::stringstream ss(a.baselines);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) a.options.baselines.push_back(item);
  if (!a.json.empty()) MCPOSE_RETURN_IF_ERROR(CheckWritable(a.json));
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<Dataset> dataset, Dataset::Open(a.dataset, a.split));

  const std::string machine = bench::MachineDescription();
  // The header comes with the first object, so that input RunBench rejects before timing
  // anything (an unknown obj_id or baseline) leaves only the error.
  bool header_printed = false;
  auto progress = [&](const bench::BenchObject& r) {
    if (!header_printed) {
      header_printed = true;
      std::printf("machine: %s\nengine %s (SIMD target %s), LOD %.2f px, pixel stride %d, %d samples, "
                  "%d iterations, threads %d\n",
                  machine.c_str(), RasterBackendName(o.backend), ActiveSimdTarget().c_str(), o.lod_error_px,
                  o.pixel_stride, o.samples, a.options.iterations, o.threads);
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
    std::fflush(stdout);
  };
  MCPOSE_ASSIGN_OR_RETURN(std::vector<bench::BenchObject> objects, bench::RunBench(*dataset, a.options, progress));

  if (!a.json.empty()) {
    nlohmann::json arr = nlohmann::json::array();
    for (const auto& r : objects) arr.push_back(ObjectJson(r));
    nlohmann::json doc = {{"machine",
                           {{"cpu", machine},
                            {"simd_targets", SimdTargets()},
                            {"threads", objects.empty() ? o.threads : objects[0].threads}}},
                          {"options",
                           {{"engine", RasterBackendName(o.backend)},
                            {"lod_px", o.lod_error_px},
                            {"lod_unbiased", o.lod_unbiased},
                            {"pixel_stride", o.pixel_stride},
                            {"max_grid_pixels", o.max_grid_pixels},
                            {"backface_culling", o.backface_culling},
                            {"cluster_culling", o.cluster_culling},
                            {"batched_setup", o.batched_setup},
                            {"simd_target", ActiveSimdTarget()},
                            {"samples", o.samples},
                            {"iterations", a.options.iterations},
                            {"render_repeats", a.options.render_repeats},
                            {"eps_m", o.eps_m},
                            {"seed", o.seed}}},
                          {"objects", arr}};
    MCPOSE_RETURN_IF_ERROR(WriteFileAtomically(a.json, doc.dump(1) + "\n"));
  }
  return Status::Ok();
}

}  // namespace

void AddBenchCommand(CLI::App& app, Status* status) {
  auto args = std::make_shared<BenchArgs>();
  EstimatorOptions& o = args->options.estimator;
  CLI::App* cmd = app.add_subcommand(
      "bench", "Time one Monte-Carlo iteration per object on real frames (ground-truth boxes), with baselines");
  cmd->add_option("--dataset", args->dataset, "Dataset root (YCB-Video native or BOP layout)")->required();
  cmd->add_option("--split", args->split, "BOP split folder")->capture_default_str();
  cmd->add_option("--objects", args->objects, "obj_ids (default: the paper's five: 2 4 5 9 10)")->delimiter(',');
  cmd->add_option("--samples", o.samples, "Samples per object")->capture_default_str();
  cmd->add_option("--iterations", args->options.iterations, "Full iterations timed per object")->capture_default_str();
  cmd->add_option("--repeats", args->options.render_repeats, "Rounds of render + inlier on the initial hypotheses: each times every baseline once and mcpose about as long")->capture_default_str();
  cmd->add_option("--threads", o.threads, "Raster cores (worker threads); 0 = all hardware threads")->capture_default_str();
  cmd->add_option("--engine", args->engine, "Raster core: scalar, fixed, simd or float-simd")->capture_default_str();
  cmd->add_option("--lod-px", o.lod_error_px, "Level-of-detail budget: measured deviation in image pixels at the box depth; 0 = full mesh")->capture_default_str();
  cmd->add_flag("--lod-unbiased,!--no-lod-unbiased", o.lod_unbiased,
                "LOD levels' vertices moved so that the full surface lies on each level on average (default on)");
  cmd->add_option("--pixel-stride", o.pixel_stride, "Score every s-th pixel in x and y of each box")->capture_default_str();
  cmd->add_option("--max-grid-pixels", o.max_grid_pixels, "Coarser stride for boxes with more grid pixels; 0 = none")->capture_default_str();
  cmd->add_flag("--backface-culling,!--no-backface-culling", o.backface_culling,
                "Cull back-facing triangles, in mcpose and in the baselines (default on)");
  cmd->add_flag("--cluster-culling,!--no-cluster-culling", o.cluster_culling,
                "Drop whole triangle clusters outside the box or (with back-face culling) facing away before setup (default on)");
  cmd->add_flag("--batched-setup,!--no-batched-setup", o.batched_setup,
                "Classify and set up triangles a SIMD vector at a time (default on)");
  AddSimdTargetOption(cmd, &args->simd_target);
  cmd->add_option("--seed", o.seed, "Random seed")->capture_default_str();
  cmd->add_option("--baselines", args->baselines, "Comma-separated: embree,osmesa (same hypotheses, same boxes)");
  cmd->add_option("--json", args->json, "Write {machine, options, objects: [...]} here");
  cmd->callback([args, status] { *status = RunBenchCommand(*args); });
}

}  // namespace mcpose::cli

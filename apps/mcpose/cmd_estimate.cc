#include <cstdio>
#include <memory>

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "commands.h"
#include "engine/pipeline.h"
#include "mcpose/dataset.h"
#include "mcpose/detection.h"
#include "mcpose/results.h"

namespace mcpose::cli {

namespace {

struct EstimateArgs {
  std::string dataset, split = "test", detections, out, out_json;
  std::string inlier = "1d";
  std::string engine = RasterBackendName(EstimatorOptions{}.backend);
  std::vector<double> weights;
  bool no_culling = false;
  bool quiet = false;
  std::string simd_target;
  EstimatorOptions options;
};

nlohmann::json ObjectJson(const ObjectRecord& r) {
  const ObjectEstimate& e = r.estimate;
  nlohmann::json R = nlohmann::json::array(), t = nlohmann::json::array();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R.push_back(e.T_cam_obj.R(i, j));
  for (int i = 0; i < 3; ++i) t.push_back(e.T_cam_obj.t(i) * 1000.0);
  return {
      {"scene_id", r.key.scene_id},
      {"im_id", r.key.image_id},
      {"obj_id", r.obj_id},
      {"name", r.name},
      {"boxes", r.num_boxes},
      {"chosen_box", {{"bbox", {r.chosen_box.x, r.chosen_box.y, r.chosen_box.w, r.chosen_box.h}},
                      {"score", r.chosen_box.score},
                      {"index", e.best_box}}},
      {"iterations", e.iterations},
      {"best_weight", e.best_weight},
      {"final_mean_weight", e.final_mean_weight},
      {"mean_weight_history", e.mean_weight_history},
      {"R", R},
      {"t_mm", t},
      {"time_s", r.time_s},
      {"box_triangles", e.box_triangles},
      {"counters", CountersJson(e.counters)},
  };
}

}  // namespace

nlohmann::json CountersJson(const EngineCounters& c) {
  return {{"triangles_full", c.triangles_full},
          {"triangles_in", c.triangles_in},
          {"culled_backface", c.culled_backface},
          {"culled_degenerate", c.culled_degenerate},
          {"culled_outside_box", c.culled_outside_box},
          {"culled_near", c.culled_near},
          {"culled_between_pixels", c.culled_between_pixels},
          {"triangles_rasterized", c.triangles_rasterized},
          {"fragments", c.fragments},
          {"clusters", c.clusters},
          {"clusters_culled_backface", c.clusters_culled_backface},
          {"clusters_culled_outside_box", c.clusters_culled_outside_box},
          {"cdf_draws", c.cdf_draws},
          {"cdf_reads", c.cdf_reads},
          {"cdf_reads_naive", c.cdf_reads_naive},
          {"depth_bytes_read", c.depth_bytes_read},
          {"depth_bytes_read_naive", c.depth_bytes_read_naive}};
}

namespace {

Status RunEstimate(EstimateArgs& a) {
  // ---- Options ------------------------------------------------------------------------
  EstimatorOptions& o = a.options;
  if (a.inlier == "1d") {
    o.inlier_mode = InlierMode::k1D;
  } else if (a.inlier == "3d") {
    o.inlier_mode = InlierMode::k3D;
  } else {
    return InvalidArgument("--inlier must be 1d or 3d, got '" + a.inlier + "'");
  }
  if (!ParseRasterBackend(a.engine, &o.backend))
    return InvalidArgument(std::string("--engine must be ") + kRasterBackendChoices + ", got '" + a.engine + "'");
  if (!a.weights.empty()) {
    if (a.weights.size() != 3) return InvalidArgument("--weights takes three numbers a b c");
    o.weight_a = a.weights[0], o.weight_b = a.weights[1], o.weight_c = a.weights[2];
  }
  o.backface_culling = !a.no_culling;
  MCPOSE_RETURN_IF_ERROR(ApplySimdTarget(a.simd_target));
  std::string error;
  if (!o.IsValid(&error)) return InvalidArgument("invalid options: " + error);

  // ---- Inputs and outputs, checked before any work -------------------------------------
  MCPOSE_RETURN_IF_ERROR(CheckWritable(a.out));
  if (!a.out_json.empty()) MCPOSE_RETURN_IF_ERROR(CheckWritable(a.out_json));
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<Dataset> dataset, Dataset::Open(a.dataset, a.split));
  MCPOSE_ASSIGN_OR_RETURN(std::vector<Detection> detections, ReadDetectionsJson(a.detections));
  if (detections.empty()) return InvalidArgument(a.detections + ": holds no detections");

  // ---- Run ------------------------------------------------------------------------------
  auto progress = [&](int done, int total, const ObjectRecord& r) {
    if (a.quiet) return;
    spdlog::info("[{}/{}] scene {} image {} obj {:2d} {:<24} boxes {} it {:2d} best w {:.3f} mean w {:.3f} {:.2f} s",
                 done, total, r.key.scene_id, r.key.image_id, r.obj_id, r.name, r.num_boxes,
                 r.estimate.iterations, r.estimate.best_weight, r.estimate.final_mean_weight, r.time_s);
  };
  MCPOSE_ASSIGN_OR_RETURN(RunReport report,
                          RunEstimation(*dataset, detections, a.detections, o, progress));

  // ---- Outputs: written only after everything succeeded ---------------------------------
  if (!a.out_json.empty()) {
    nlohmann::json objects = nlohmann::json::array();
    for (const auto& r : report.objects) objects.push_back(ObjectJson(r));
    nlohmann::json doc = {{"dataset", a.dataset},
                          {"detections", a.detections},
                          {"options",
                           {{"samples", o.samples},
                            {"max_iterations", o.max_iterations},
                            {"tau", o.tau},
                            {"seed", o.seed},
                            {"inlier", a.inlier},
                            {"eps_m", o.eps_m},
                            {"weights", {o.weight_a, o.weight_b, o.weight_c}},
                            {"engine", RasterBackendName(o.backend)},
                            {"lod_px", o.lod_error_px},
                            {"lod_unbiased", o.lod_unbiased},
                            {"occlusion_aware", o.occlusion_aware},
                            {"pixel_stride", o.pixel_stride},
                            {"max_grid_pixels", o.max_grid_pixels},
                            {"cluster_culling", o.cluster_culling},
                            {"batched_setup", o.batched_setup},
                            {"simd_target", ActiveSimdTarget()},
                            {"threads", o.threads}}},
                          {"objects", objects}};
    MCPOSE_RETURN_IF_ERROR(WriteFileAtomically(a.out_json, doc.dump(1) + "\n"));
  }
  MCPOSE_RETURN_IF_ERROR(WriteResultsCsv(a.out, report.results));

  if (!a.quiet) {
    double total_s = 0;
    int iterations = 0;
    for (const auto& r : report.objects) total_s += r.time_s, iterations += r.estimate.iterations;
    std::printf("%zu objects in %zu result rows, %.1f s, %.1f ms per iteration; results: %s\n",
                report.objects.size(), report.results.size(), total_s,
                iterations ? 1000.0 * total_s / iterations : 0.0, a.out.c_str());
  }
  return Status::Ok();
}

}  // namespace

void AddEstimateCommand(CLI::App& app, Status* status) {
  auto args = std::make_shared<EstimateArgs>();
  EstimatorOptions& o = args->options;
  CLI::App* cmd = app.add_subcommand("estimate", "Estimate one 6-DoF pose per (image, class) from 2D detections");
  cmd->add_option("--dataset", args->dataset, "Dataset root (YCB-Video native or BOP layout, auto-detected)")->required();
  cmd->add_option("--split", args->split, "BOP split folder")->capture_default_str();
  cmd->add_option("--detections", args->detections, "BOP default-detections JSON")->required();
  cmd->add_option("--out", args->out, "Results CSV (BOP format: scene_id,im_id,obj_id,score,R,t,time)")->required();
  cmd->add_option("--out-json", args->out_json, "Per-object detail: iterations, weights, chosen box, engine counters");
  cmd->add_option("--samples", o.samples, "Samples per object class per image")->capture_default_str();
  cmd->add_option("--iterations", o.max_iterations, "Iteration limit")->capture_default_str();
  cmd->add_option("--tau", o.tau, "Stop when the mean weight exceeds tau")->capture_default_str();
  cmd->add_option("--threads", o.threads, "Raster cores (worker threads); 0 = all hardware threads")->capture_default_str();
  cmd->add_option("--seed", o.seed, "Random seed; same seed, same results at any thread count")->capture_default_str();
  cmd->add_option("--inlier", args->inlier, "Inlier test: 1d (|z_r - z_o| < eps) or 3d (nearest observed point)")->capture_default_str();
  cmd->add_option("--eps", o.eps_m, "Inlier threshold, metres")->capture_default_str();
  char weights_help[128];
  std::snprintf(weights_help, sizeof weights_help,
                "Weight coefficients a b c (sum 1): w = a N/N_b + b N/N_r + c score (default %.2f %.2f %.2f)",
                o.weight_a, o.weight_b, o.weight_c);
  cmd->add_option("--weights", args->weights, weights_help)->expected(3);
  cmd->add_option("--keep-top", o.keep_top_fraction, "Resample from this best fraction of samples, (0, 1]")->capture_default_str();
  cmd->add_option("--cdf-table", o.cdf_table_size, "Entries of the coarse CDF threshold table")->capture_default_str();
  cmd->add_option("--sigma-t", o.sigma_t_m, "Diffusion: translation sigma at iteration 0, metres")->capture_default_str();
  cmd->add_option("--sigma-r", o.sigma_r_rad, "Diffusion: rotation sigma at iteration 0, radians")->capture_default_str();
  cmd->add_option("--sigma-t-min", o.sigma_t_min_m, "Diffusion: smallest translation sigma, metres")->capture_default_str();
  cmd->add_option("--sigma-r-min", o.sigma_r_min_rad, "Diffusion: smallest rotation sigma, radians")->capture_default_str();
  cmd->add_option("--anneal", o.anneal, "Diffusion: sigma factor per iteration, (0, 1]")->capture_default_str();
  cmd->add_option("--flip-rate", o.flip_rate, "Diffusion: probability that a resampled sample turns 180 degrees about a model axis, [0, 1]")->capture_default_str();
  cmd->add_option("--init-sigma-t", o.init_sigma_t_m, "Initial translation jitter, metres")->capture_default_str();
  cmd->add_option("--init-depth-quantile", o.init_depth_quantile, "Quantile of the box's valid depths for the initial distance")->capture_default_str();
  cmd->add_option("--engine", args->engine, "Raster core: scalar (float reference), fixed (1/16-pixel fixed point), simd (fixed point, Highway rows) or float-simd (the float reference a vector at a time, same results)")->capture_default_str();
  cmd->add_option("--pixel-stride", o.pixel_stride, "Score every s-th pixel in x and y of each box; 1 with --max-grid-pixels 0 = every pixel")->capture_default_str();
  cmd->add_option("--max-grid-pixels", o.max_grid_pixels, "Sample a box with more grid pixels than this at a coarser stride; 0 = no budget")->capture_default_str();
  cmd->add_option("--lod-px", o.lod_error_px, "Level of detail: coarsest simplified mesh whose measured deviation from the full mesh is within this many image pixels at the box depth; 0 = full mesh")->capture_default_str();
  cmd->add_flag("--lod-unbiased,!--no-lod-unbiased", o.lod_unbiased,
                "LOD levels' vertices moved so that the full surface lies on each level on average (default on; --no-lod-unbiased: meshoptimizer's vertices, levels inside the full surface where it bulges)");
  cmd->add_flag("--occlusion-aware,!--no-occlusion-aware", o.occlusion_aware,
                "Leave rendered pixels hidden behind observed surfaces out of N_r (default on; --no-occlusion-aware: the paper's N_r)");
  cmd->add_flag("--no-backface-culling", args->no_culling, "Rasterize back faces too");
  cmd->add_flag("--cluster-culling,!--no-cluster-culling", o.cluster_culling,
                "Drop whole triangle clusters outside the box or (with back-face culling) facing away before setup (fixed, simd; with LOD; default on)");
  cmd->add_flag("--batched-setup,!--no-batched-setup", o.batched_setup,
                "Classify and set up triangles a SIMD vector at a time (fixed, simd; same results; default on)");
  AddSimdTargetOption(cmd, &args->simd_target);
  cmd->add_flag("-q,--quiet", args->quiet, "No progress output");
  cmd->callback([args, status] { *status = RunEstimate(*args); });
}

}  // namespace mcpose::cli

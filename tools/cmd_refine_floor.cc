#include <cstdio>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "mcpose/analysis/refine_floor.h"
#include "cli/common.h"
#include "mcpose/io_util.h"
#include "tools.h"
#include "mcpose/dataset.h"

namespace mcpose::tools {

using cli::CheckWritable;

namespace {

struct RefineFloorArgs {
  std::string dataset, split = "test", json;
  RefineOptions refine;  // the estimator's alignment settings
  analysis::RefineFloorOptions floor;
};

nlohmann::json RowJson(const analysis::RefineFloorReport::Row& r) {
  return {{"obj_id", r.obj_id},
          {"name", r.name},
          {"instances", r.instances},
          {"mean_start_adds_mm", r.mean_start_mm},
          {"mean_aligned_adds_mm", r.mean_aligned_mm},
          {"median_aligned_adds_mm", r.median_aligned_mm},
          {"mean_across_ray_mm", r.mean_across_ray_mm},
          {"adds_auc", r.auc}};
}

Status RunRefineFloor(RefineFloorArgs& a) {
  a.floor.refine = a.refine;
  std::string error;
  if (!a.floor.IsValid(&error)) return InvalidArgument("invalid refine-floor options: " + error);
  if (!a.json.empty()) MCPOSE_RETURN_IF_ERROR(CheckWritable(a.json));
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<Dataset> dataset, Dataset::Open(a.dataset, a.split));
  MCPOSE_RETURN_IF_ERROR(cli::CheckOutputsOutsideDataset(*dataset, {{"--json", a.json}}));
  MCPOSE_ASSIGN_OR_RETURN(analysis::RefineFloorReport report,
                          analysis::AnalyzeRefineFloor(*dataset, a.floor, &PrintFrameProgress));
  std::printf("Depth alignment (%d steps, Tukey %.1f mm, pairs within %.0f mm) of each ground-truth pose, started\n"
              "%.1f mm and %.1f deg from it, in its visible-mask box grown by %.0f%% per side: ADD-S of the\n"
              "aligned pose to the truth (the truth and the depth disagree by this much), and the ADD-S AUC\n"
              "(up to %.0f cm) of the aligned poses.\n",
              a.floor.refine.max_iterations, 1000 * a.floor.refine.tukey_m, 1000 * a.floor.refine.max_distance_m,
              a.floor.start_mm, a.floor.start_deg, 100 * a.floor.box_margin, 100 * a.floor.auc_max_m);
  std::printf("%-24s %5s %10s %12s %14s %12s %8s\n", "object", "inst", "start mm", "aligned mm", "aligned median",
              "across ray", "AUC");
  auto row = [](const analysis::RefineFloorReport::Row& x) {
    std::printf("%-24s %5d %10.2f %12.2f %14.2f %12.2f %8.2f\n", x.name.c_str(), x.instances, x.mean_start_mm,
                x.mean_aligned_mm, x.median_aligned_mm, x.mean_across_ray_mm, 100 * x.auc);
  };
  for (const auto& x : report.per_object) row(x);
  row(report.overall);
  if (!a.json.empty()) {
    nlohmann::json inst = nlohmann::json::array();
    for (const auto& i : report.instances)
      inst.push_back({{"scene_id", i.key.scene_id}, {"im_id", i.key.image_id}, {"obj_id", i.obj_id},
                      {"adds_start_mm", 1000 * i.adds_start_m}, {"adds_aligned_mm", 1000 * i.adds_aligned_m},
                      {"along_ray_mm", i.along_ray_mm}, {"across_ray_mm", i.across_ray_mm},
                      {"iterations", i.iterations}});
    nlohmann::json rows = nlohmann::json::array();
    for (const auto& x : report.per_object) rows.push_back(RowJson(x));
    nlohmann::json doc = {{"options",
                           {{"start_mm", a.floor.start_mm}, {"start_deg", a.floor.start_deg},
                            {"box_margin", a.floor.box_margin}, {"seed", a.floor.seed},
                            {"iterations", a.floor.refine.max_iterations}, {"tukey_m", a.floor.refine.tukey_m},
                            {"max_distance_m", a.floor.refine.max_distance_m}}},
                          {"overall", RowJson(report.overall)},
                          {"per_object", rows},
                          {"instances", inst}};
    MCPOSE_RETURN_IF_ERROR(io::WriteFileAtomic(a.json, doc.dump(1) + "\n"));
  }
  return Status::Ok();
}

}  // namespace

void AddRefineFloorCommand(CLI::App& app, Status* status) {
  auto args = std::make_shared<RefineFloorArgs>();
  CLI::App* cmd = app.add_subcommand(
      "refine-floor",
      "How far the refinement's depth alignment, started at (or near) each ground-truth pose, lands from it: the "
      "disagreement of truth and depth that bounds what refinement can add");
  cmd->add_option("--dataset", args->dataset, "Dataset root (YCB-Video native or BOP layout)")->required();
  cmd->add_option("--split", args->split, "BOP split folder")->capture_default_str();
  cmd->add_option("--start-mm", args->floor.start_mm, "Start this far from the truth, mm (random direction)")
      ->capture_default_str();
  cmd->add_option("--start-deg", args->floor.start_deg, "and turned this far, degrees (random axis)")
      ->capture_default_str();
  cmd->add_option("--box-margin", args->floor.box_margin, "Visible-mask box grown by this share of its size per side")
      ->capture_default_str();
  cmd->add_option("--seed", args->floor.seed, "Seed of the random starts")->check(SeedCheck())->capture_default_str();
  cmd->add_option("--iterations", args->refine.max_iterations, "Alignment steps (the estimator's --refine-iterations)")
      ->capture_default_str();
  cmd->add_option("--tukey", args->refine.tukey_m, "Robust loss scale of the alignment, metres")->capture_default_str();
  cmd->add_option("--pair-distance", args->refine.max_distance_m,
                  "Model and observed points farther apart are not paired, metres")->capture_default_str();
  cmd->add_option("--json", args->json, "Also write per-instance errors and the summary as JSON");
  cmd->callback([args, status] { *status = RunRefineFloor(*args); });
}

}  // namespace mcpose::tools

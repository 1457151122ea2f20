#include <cstdio>
#include <memory>

#include <nlohmann/json.hpp>

#include "mcpose/analysis/depth_ambiguity.h"
#include "cli/common.h"
#include "mcpose/io_util.h"
#include "tools.h"
#include "mcpose/dataset.h"

namespace mcpose::tools {

using cli::CheckWritable;

namespace {

struct AmbiguityArgs {
  std::string dataset, split = "test", json;
  analysis::AmbiguityOptions options;
};

Status RunAmbiguity(const AmbiguityArgs& a) {
  if (!a.json.empty()) MCPOSE_RETURN_IF_ERROR(CheckWritable(a.json));
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<Dataset> dataset, Dataset::Open(a.dataset, a.split));
  MCPOSE_RETURN_IF_ERROR(cli::CheckOutputsOutsideDataset(*dataset, {{"--json", a.json}}));
  MCPOSE_ASSIGN_OR_RETURN(analysis::AmbiguityReport report, analysis::AnalyzeDataset(*dataset, a.options, &PrintFrameProgress));
  std::printf("Depth-equivalent poses of each ground-truth instance (turns of %.0f deg about the model axes, with\n"
              "180 deg flips; equivalent = renders agree within %.1f mm on >= %.0f%% of the unoccluded pixels).\n"
              "ceiling: expected ADD(-S) < %.0f cm of an estimator that sees only depth and picks at random\n"
              "among the equivalent poses (ADD-S for 024, 036, 051, 052, 061).\n",
              a.options.step_deg, 1000 * a.options.agree_eps_m, 100 * a.options.min_agreement,
              100 * a.options.threshold_m);
  std::printf("%-24s %5s %12s %9s\n", "object", "inst", "equivalent", "ceiling");
  auto row = [](const analysis::AmbiguityReport::Row& r) {
    std::printf("%-24s %5d %12.1f %8.1f%%\n", r.name.c_str(), r.instances, r.mean_equivalent, 100 * r.ceiling);
  };
  for (const auto& r : report.per_object) row(r);
  row(report.overall);
  if (!a.json.empty()) {
    nlohmann::json inst = nlohmann::json::array();
    for (const auto& i : report.instances)
      inst.push_back({{"scene_id", i.key.scene_id}, {"im_id", i.key.image_id}, {"obj_id", i.obj_id},
                      {"candidates", i.candidates}, {"equivalent", i.equivalent},
                      {"equivalent_correct", i.equivalent_correct}, {"ceiling", i.ceiling}});
    nlohmann::json rows = nlohmann::json::array();
    for (const auto& r : report.per_object)
      rows.push_back({{"obj_id", r.obj_id}, {"name", r.name}, {"instances", r.instances},
                      {"mean_equivalent", r.mean_equivalent}, {"ceiling", r.ceiling}});
    nlohmann::json doc = {{"options", {{"step_deg", a.options.step_deg}, {"agree_eps_m", a.options.agree_eps_m},
                                       {"min_agreement", a.options.min_agreement},
                                       {"occlusion_eps_m", a.options.occlusion_eps_m},
                                       {"threshold_m", a.options.threshold_m}}},
                          {"overall", {{"instances", report.overall.instances},
                                       {"mean_equivalent", report.overall.mean_equivalent},
                                       {"ceiling", report.overall.ceiling}}},
                          {"per_object", rows}, {"instances", inst}};
    MCPOSE_RETURN_IF_ERROR(io::WriteFileAtomic(a.json, doc.dump(1) + "\n"));
  }
  return Status::Ok();
}

}  // namespace

void AddAmbiguityCommand(CLI::App& app, Status* status) {
  auto args = std::make_shared<AmbiguityArgs>();
  CLI::App* cmd = app.add_subcommand(
      "ambiguity", "How many poses depth alone cannot tell from the ground truth, and the ADD(-S) ceiling that sets");
  cmd->add_option("--dataset", args->dataset, "Dataset root (YCB-Video native or BOP layout)")->required();
  cmd->add_option("--split", args->split, "BOP split folder")->capture_default_str();
  cmd->add_option("--step-deg", args->options.step_deg, "Rotation step about each model axis, degrees")->capture_default_str();
  cmd->add_option("--agree-m", args->options.agree_eps_m, "Renders agree at a pixel within this depth, metres")->capture_default_str();
  cmd->add_option("--min-agreement", args->options.min_agreement, "Share of pixels that must agree")->capture_default_str();
  cmd->add_option("--threshold", args->options.threshold_m, "ADD(-S) threshold, metres")->capture_default_str();
  cmd->add_option("--json", args->json, "Also write per-instance counts and the summary as JSON");
  cmd->callback([args, status] { *status = RunAmbiguity(*args); });
}

}  // namespace mcpose::tools

#include <cmath>
#include <cstdio>
#include <memory>

#include <nlohmann/json.hpp>

#include "cli/common.h"
#include "engine/pipeline.h"
#include "io/io_util.h"
#include "commands.h"
#include "mcpose/dataset.h"
#include "mcpose/detection.h"
#include "mcpose/eval.h"
#include "mcpose/results.h"

namespace mcpose::cli {

namespace {

struct EvalArgs {
  std::string dataset, split = "test", results, detections, json;
  double auc_max_m = 0.10;
};

void PrintRow(const AccuracySummary& s) {
  std::printf("%-24s %4d %4d | %6.1f %6.1f %6.1f | %6.1f %6.1f %6.1f | %6.1f %6.1f %6.1f\n",
              s.name.c_str(), s.instances, s.with_result, 100 * s.add_lt_2cm, 100 * s.add_lt_4cm,
              100 * s.add_auc, 100 * s.adds_lt_2cm, 100 * s.adds_lt_4cm, 100 * s.adds_auc,
              100 * s.add_s_lt_2cm, 100 * s.add_s_lt_4cm, 100 * s.add_s_auc);
}

nlohmann::json SummaryJson(const AccuracySummary& s) {
  return {{"obj_id", s.obj_id},           {"name", s.name},
          {"instances", s.instances},     {"with_result", s.with_result},
          {"add_lt_2cm", s.add_lt_2cm},   {"add_lt_4cm", s.add_lt_4cm},
          {"add_auc", s.add_auc},         {"adds_lt_2cm", s.adds_lt_2cm},
          {"adds_lt_4cm", s.adds_lt_4cm}, {"adds_auc", s.adds_auc},
          {"add_s_lt_2cm", s.add_s_lt_2cm}, {"add_s_lt_4cm", s.add_s_lt_4cm},
          {"add_s_auc", s.add_s_auc}};
}

// JSON has no infinity: missing results are written as null.
nlohmann::json Metres(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

Status RunEval(const EvalArgs& a) {
  if (!(std::isfinite(a.auc_max_m) && a.auc_max_m > 0)) return InvalidArgument("--auc-max must be > 0");
  MCPOSE_RETURN_IF_ERROR(CheckOutputsDistinct({{"--results", a.results}, {"--detections", a.detections}}, {{"--json", a.json}}));
  if (!a.json.empty()) MCPOSE_RETURN_IF_ERROR(CheckWritable(a.json));
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<Dataset> dataset, Dataset::Open(a.dataset, a.split));
  MCPOSE_RETURN_IF_ERROR(CheckOutputsOutsideDataset(*dataset, {{"--json", a.json}}));
  MCPOSE_ASSIGN_OR_RETURN(std::vector<PoseResult> results, ReadResultsCsv(a.results));
  std::vector<Detection> detections;
  if (!a.detections.empty()) {
    MCPOSE_ASSIGN_OR_RETURN(detections, ReadDetectionsJson(a.detections));
    MCPOSE_RETURN_IF_ERROR(CheckDetectionsAgainstDataset(*dataset, detections, a.detections));
  }
  EvalOptions options;
  options.auc_max_m = a.auc_max_m;
  MCPOSE_ASSIGN_OR_RETURN(EvalReport report, Evaluate(*dataset, results, a.detections.empty() ? nullptr : &detections, options));

  std::printf("ADD(-S) uses ADD-S for the YCB-Video symmetric set (024, 036, 051, 052, 061). "
              "Shares in %%; AUC up to %.0f cm.\n", 100 * a.auc_max_m);
  std::printf("%-24s %4s %4s | %6s %6s %6s | %6s %6s %6s | %6s %6s %6s\n", "object", "inst", "res",
              "ADD<2", "ADD<4", "AUC", "ADDS<2", "ADDS<4", "AUC", "(-S)<2", "(-S)<4", "AUC");
  for (const auto& s : report.per_object) PrintRow(s);
  PrintRow(report.overall);
  if (report.unmatched_rows > 0) {
    std::printf("%d of %zu result rows match no target (no visible ground-truth instance of their object in an "
                "evaluated image): not scored.\n", report.unmatched_rows, results.size());
  }

  if (!a.json.empty()) {
    nlohmann::json inst = nlohmann::json::array();
    for (const auto& e : report.instances) {
      inst.push_back({{"scene_id", e.key.scene_id}, {"im_id", e.key.image_id}, {"obj_id", e.obj_id},
                      {"gt_index", e.gt_index}, {"visible_pixels", e.visible_pixels},
                      {"has_result", e.has_result}, {"add_m", Metres(e.add_m)},
                      {"adds_m", Metres(e.adds_m)}, {"add_or_adds_m", Metres(e.add_or_adds_m)},
                      {"rotation_error_deg", Metres(e.rotation_error_deg)},
                      {"rotation_error_axis", e.has_result ? nlohmann::json({e.rotation_error_axis.x(), e.rotation_error_axis.y(),
                                                                             e.rotation_error_axis.z()})
                                                           : nlohmann::json()},
                      {"translation_error_mm", Metres(e.translation_error_mm)}});
    }
    nlohmann::json per_object = nlohmann::json::array();
    for (const auto& s : report.per_object) per_object.push_back(SummaryJson(s));
    nlohmann::json doc = {{"results", a.results}, {"overall", SummaryJson(report.overall)},
                          {"per_object", per_object}, {"unmatched_rows", report.unmatched_rows},
                          {"instances", inst}};
    MCPOSE_RETURN_IF_ERROR(io::WriteFileAtomic(a.json, doc.dump(1) + "\n"));
  }
  return Status::Ok();
}

struct GtDetArgs {
  std::string dataset, split = "test", out;
  GtDetectionOptions options;
};

Status RunDetectionsFromGt(const GtDetArgs& a) {
  const auto& o = a.options;
  if (!(o.jitter >= 0 && o.jitter < 0.5)) return InvalidArgument("--jitter must lie in [0, 0.5)");
  if (!(o.distractors >= 0 && o.distractors <= 1)) return InvalidArgument("--distractors must lie in [0, 1]");
  MCPOSE_RETURN_IF_ERROR(CheckWritable(a.out));
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<Dataset> dataset, Dataset::Open(a.dataset, a.split));
  MCPOSE_RETURN_IF_ERROR(CheckOutputsOutsideDataset(*dataset, {{"--out", a.out}}));
  MCPOSE_ASSIGN_OR_RETURN(std::vector<Detection> dets, DetectionsFromGroundTruth(*dataset, o));
  MCPOSE_RETURN_IF_ERROR(WriteDetectionsJson(a.out, dets));
  std::printf("%zu detections written to %s\n", dets.size(), a.out.c_str());
  return Status::Ok();
}

}  // namespace

void AddEvalCommand(CLI::App& app, Status* status) {
  auto args = std::make_shared<EvalArgs>();
  CLI::App* cmd = app.add_subcommand(
      "eval", "ADD, ADD-S and ADD(-S) accuracy of a results CSV against the ground truth (YCB-Video protocol)");
  cmd->add_option("--dataset", args->dataset, "Dataset root (YCB-Video native or BOP layout)")->required();
  cmd->add_option("--split", args->split, "BOP split folder")->capture_default_str();
  cmd->add_option("--results", args->results, "Results CSV in the BOP format")->required();
  cmd->add_option("--detections", args->detections,
                  "Evaluate only the images that appear in this detections JSON");
  cmd->add_option("--auc-max", args->auc_max_m, "Upper end of the AUC threshold range, metres")->capture_default_str();
  cmd->add_option("--json", args->json, "Also write per-instance errors and the summary as JSON");
  cmd->callback([args, status] { *status = RunEval(*args); });
}

void AddDetectionsFromGtCommand(CLI::App& app, Status* status) {
  auto args = std::make_shared<GtDetArgs>();
  CLI::App* cmd = app.add_subcommand(
      "detections-from-gt", "Detector-like boxes (jittered, with distractors) from the ground-truth visible masks");
  cmd->add_option("--dataset", args->dataset, "Dataset root (YCB-Video native or BOP layout)")->required();
  cmd->add_option("--split", args->split, "BOP split folder")->capture_default_str();
  cmd->add_option("--out", args->out, "Detections JSON to write (BOP default-detections format)")->required();
  cmd->add_option("--jitter", args->options.jitter, "Each side moves by up to this fraction of the box size")->capture_default_str();
  cmd->add_option("--distractors", args->options.distractors, "Probability of an extra same-class box elsewhere")->capture_default_str();
  cmd->add_option("--seed", args->options.seed, "Random seed")->check(SeedCheck())->capture_default_str();
  cmd->callback([args, status] { *status = RunDetectionsFromGt(*args); });
}

}  // namespace mcpose::cli

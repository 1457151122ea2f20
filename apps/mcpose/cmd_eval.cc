#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>

#include <nlohmann/json.hpp>

#include "cli/common.h"
#include "mcpose/run.h"
#include "mcpose/io_util.h"
#include "commands.h"
#include "mcpose/bop19.h"
#include "mcpose/dataset.h"
#include "mcpose/detection.h"
#include "mcpose/eval.h"
#include "mcpose/results.h"

namespace mcpose::cli {

namespace {

struct EvalArgs {
  std::string dataset, split = "test", results, detections, json, models_info, targets;
  std::vector<std::string> metrics = {"ycbv"};
  double auc_max_m = 0.10;
};

void PrintBop19Row(const Bop19Summary& s) {
  std::printf("%-24s %7d | %6.1f %6.1f %6.1f | %6.1f\n", s.name.c_str(), s.targets, 100 * s.ar_vsd, 100 * s.ar_mssd,
              100 * s.ar_mspd, 100 * s.ar);
}

nlohmann::json Bop19Json(const Bop19Summary& s) {
  return {{"obj_id", s.obj_id}, {"name", s.name},       {"targets", s.targets}, {"ar_vsd", s.ar_vsd},
          {"ar_mssd", s.ar_mssd}, {"ar_mspd", s.ar_mspd}, {"ar", s.ar}};
}

// What the BOP19 metrics need besides the results: the objects' diameters and symmetries, and
// the targets (none: every instance at least 10 % visible). From the flags, else from a BOP
// dataset's own files; read before any work.
struct Bop19Inputs {
  std::string info_path, targets_path;
  std::map<int, ModelInfo> models_info;
  std::optional<std::vector<Bop19Target>> targets;
};

StatusOr<Bop19Inputs> ReadBop19Inputs(const EvalArgs& a, const Dataset& dataset) {
  Bop19Inputs in{a.models_info, a.targets, {}, std::nullopt};
  if (dataset.format() == DatasetFormat::kBop) {
    if (in.info_path.empty()) in.info_path = dataset.root() + "/models/models_info.json";
    std::error_code ec;
    if (in.targets_path.empty() && a.split == "test" &&
        std::filesystem::is_regular_file(dataset.root() + "/test_targets_bop19.json", ec))
      in.targets_path = dataset.root() + "/test_targets_bop19.json";
  }
  if (in.info_path.empty())
    return InvalidArgument("--metrics bop19 needs the objects' diameters and symmetries: --models-info FILE (a BOP "
                           "models_info.json of the same objects, e.g. BOP's ycbv models/models_info.json)");
  MCPOSE_ASSIGN_OR_RETURN(in.models_info, ReadModelsInfo(in.info_path));
  if (!in.targets_path.empty()) {
    MCPOSE_ASSIGN_OR_RETURN(in.targets, ReadBop19Targets(in.targets_path));
  }
  return in;
}

// The BOP19 metrics of `results`, printed, and returned as JSON for --json.
StatusOr<nlohmann::json> RunBop19(const Bop19Inputs& in, const Dataset& dataset, const std::vector<PoseResult>& results,
                                  const std::vector<Detection>* detections) {
  std::optional<std::set<FrameKey>> frames;
  if (detections != nullptr) {
    frames.emplace();
    for (const Detection& d : *detections) frames->insert(FrameKey{d.scene_id, d.image_id});
  }
  MCPOSE_ASSIGN_OR_RETURN(const Bop19Report report,
                          EvaluateBop19(dataset, results, in.models_info, in.targets ? &*in.targets : nullptr,
                                        Bop19Options(), frames ? &*frames : nullptr));
  std::printf("\nBOP19 average recall (%%; targets %s; VSD delta 15 mm, taus and thresholds 0.05-0.5; MSSD 0.05-0.5 "
              "of the diameter; MSPD 5-50 px at 640 px width):\n",
              in.targets ? in.targets_path.c_str() : "every instance at least 10 % visible");
  std::printf("%-24s %7s | %6s %6s %6s | %6s\n", "object", "targets", "VSD", "MSSD", "MSPD", "AR");
  for (const Bop19Summary& s : report.per_object) PrintBop19Row(s);
  PrintBop19Row(report.overall);
  nlohmann::json per_object = nlohmann::json::array();
  for (const Bop19Summary& s : report.per_object) per_object.push_back(Bop19Json(s));
  // Per scene (a video of YCB-Video): the recalls of its targets alone.
  std::map<int, std::vector<const Bop19Instance*>> by_scene;
  for (const Bop19Instance& i : report.instances) by_scene[i.key.scene_id].push_back(&i);
  nlohmann::json per_scene = nlohmann::json::array();
  for (const auto& [scene_id, instances] : by_scene) {
    nlohmann::json row = Bop19Json(Bop19Recalls(instances, Bop19Options()));
    row.erase("obj_id"), row.erase("name");
    row["scene_id"] = scene_id;
    per_scene.push_back(row);
  }
  return nlohmann::json{{"models_info", in.info_path},
                        {"targets", in.targets ? nlohmann::json(in.targets_path) : nlohmann::json()},
                        {"overall", Bop19Json(report.overall)},
                        {"per_object", per_object},
                        {"per_scene", per_scene}};
}

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
  const std::set<std::string> metrics(a.metrics.begin(), a.metrics.end());
  for (const std::string& m : metrics)
    if (m != "ycbv" && m != "bop19") return InvalidArgument("--metrics takes ycbv, bop19 or both, got '" + m + "'");
  MCPOSE_RETURN_IF_ERROR(CheckOutputsDistinct(
      {{"--results", a.results}, {"--detections", a.detections}, {"--models-info", a.models_info}, {"--targets", a.targets}},
      {{"--json", a.json}}));
  if (!a.json.empty()) MCPOSE_RETURN_IF_ERROR(CheckWritable(a.json));
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<Dataset> dataset, Dataset::Open(a.dataset, a.split));
  MCPOSE_RETURN_IF_ERROR(CheckOutputsOutsideDataset(*dataset, {{"--json", a.json}}));
  MCPOSE_ASSIGN_OR_RETURN(std::vector<PoseResult> results, ReadResultsCsv(a.results));
  std::vector<Detection> detections;
  if (!a.detections.empty()) {
    MCPOSE_ASSIGN_OR_RETURN(detections, ReadDetectionsJson(a.detections));
    MCPOSE_RETURN_IF_ERROR(CheckDetectionsAgainstDataset(*dataset, detections, a.detections));
  }
  std::optional<Bop19Inputs> bop19;
  if (metrics.contains("bop19")) {
    MCPOSE_ASSIGN_OR_RETURN(bop19, ReadBop19Inputs(a, *dataset));
  }
  nlohmann::json doc = {{"results", a.results}};
  if (metrics.contains("ycbv")) {
    EvalOptions options;
    options.auc_max_m = a.auc_max_m;
    MCPOSE_ASSIGN_OR_RETURN(EvalReport report,
                            Evaluate(*dataset, results, a.detections.empty() ? nullptr : &detections, options));
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
    doc["overall"] = SummaryJson(report.overall);
    doc["per_object"] = per_object;
    doc["unmatched_rows"] = report.unmatched_rows;
    doc["instances"] = inst;
  }
  if (bop19) {
    MCPOSE_ASSIGN_OR_RETURN(doc["bop19"], RunBop19(*bop19, *dataset, results, a.detections.empty() ? nullptr : &detections));
  }
  if (!a.json.empty()) MCPOSE_RETURN_IF_ERROR(io::WriteFileAtomic(a.json, doc.dump(1) + "\n"));
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
      "eval", "Accuracy of a results CSV against the ground truth: ADD, ADD-S and ADD(-S) (YCB-Video protocol) and the "
              "BOP19 average recall (VSD, MSSD, MSPD)");
  cmd->add_option("--dataset", args->dataset, "Dataset root (YCB-Video native or BOP layout)")->required();
  cmd->add_option("--split", args->split, "BOP split folder")->capture_default_str();
  cmd->add_option("--results", args->results, "Results CSV in the BOP format")->required();
  cmd->add_option("--detections", args->detections,
                  "Evaluate only the images that appear in this detections JSON");
  cmd->add_option("--auc-max", args->auc_max_m, "Upper end of the AUC threshold range, metres")->capture_default_str();
  cmd->add_option("--json", args->json, "Also write per-instance errors and the summary as JSON");
  cmd->add_option("--metrics", args->metrics,
                  "ycbv (ADD, ADD-S, ADD(-S)), bop19 (VSD, MSSD, MSPD and AR), or both: ycbv,bop19")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--models-info", args->models_info,
                  "BOP models_info.json with the objects' diameters and symmetries (bop19; default: a BOP dataset's own)");
  cmd->add_option("--targets", args->targets,
                  "BOP test_targets_bop19.json (bop19; default: a BOP dataset's own, else every instance at least "
                  "10 % visible)");
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

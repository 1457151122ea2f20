#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "mcpose/analysis/miss_weight.h"
#include "cli/common.h"
#include "mcpose/io_util.h"
#include "tools.h"
#include "mcpose/dataset.h"
#include "mcpose/detection.h"
#include "mcpose/eval.h"
#include "mcpose/results.h"

namespace mcpose::tools {

using cli::CheckWritable;

namespace {

struct MissesArgs {
  std::string dataset, split = "test", models, detections, results, json;
  int scene = -2;  // -2 (no scene id, the synthetic frames being -1): every scene
  double min_adds_mm = 10;
  bool as_filter = false;
  EstimatorFlags flags;
};

Status RunMisses(MissesArgs& a) {
  MCPOSE_RETURN_IF_ERROR(a.flags.Finish());
  if (!(a.min_adds_mm >= 0)) return InvalidArgument("--min-adds-mm must be >= 0");
  MCPOSE_RETURN_IF_ERROR(cli::CheckOutputsDistinct({{"--detections", a.detections}, {"--results", a.results}}, {{"--json", a.json}}));
  if (!a.json.empty()) MCPOSE_RETURN_IF_ERROR(CheckWritable(a.json));
  const EstimatorOptions& o = a.flags.options;
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<Dataset> dataset, Dataset::Open(a.dataset, a.split, a.models));
  MCPOSE_RETURN_IF_ERROR(cli::CheckOutputsOutsideDataset(*dataset, {{"--json", a.json}}));
  MCPOSE_ASSIGN_OR_RETURN(std::vector<Detection> detections, ReadDetectionsJson(a.detections));
  MCPOSE_ASSIGN_OR_RETURN(std::vector<PoseResult> results, ReadResultsCsv(a.results));
  if (a.scene != -2) {
    std::erase_if(detections, [&](const Detection& d) { return d.scene_id != a.scene; });
    std::erase_if(results, [&](const PoseResult& r) { return r.scene_id != a.scene; });
    if (detections.empty()) return InvalidArgument(a.detections + ": no box in scene " + std::to_string(a.scene));
  }
  MCPOSE_ASSIGN_OR_RETURN(EvalReport eval, Evaluate(*dataset, results, &detections, EvalOptions{}));
  analysis::Scorer scorer(o);
  std::map<int, Mesh> meshes;
  const auto number = [](double v) {
    char text[16];
    std::snprintf(text, sizeof text, "%g", v);
    return std::string(text);
  };
  const std::string beyond = ">" + number(std::end(analysis::kBasinSteps)[-1]);  // no step reaches the estimate
  const auto step = [&](double v) { return std::isinf(v) ? beyond : number(v); };
  std::string steps;
  for (double s : analysis::kBasinSteps) steps += (steps.empty() ? "" : ", ") + number(s);
  std::printf("Answers with ADD-S >= %.1f mm: %s weight of the estimate and of the truth aligned to\n"
              "the depth, each at its best over the class's boxes. search: the truth weighs more (the filter\n"
              "did not find it); weight: the estimate weighs as much or more. basin (search failures): the\n"
              "smallest turn about a model axis (deg) and move along a camera axis (mm) of the aligned truth,\n"
              "of %s, at which it no longer outweighs the estimate (%s: at none).\n",
              a.min_adds_mm, a.as_filter ? "the filter's (its level of detail and pixel stride)" : "full-resolution",
              steps.c_str(), beyond.c_str());
  std::printf("%-10s %-24s %9s %10s %5s %10s %5s %12s %8s %10s %9s\n", "scene/im", "object", "ADD-S mm", "estimate",
              "box", "truth", "box", "truth mm", "failure", "basin deg", "basin mm");
  std::vector<double> turns, moves;
  nlohmann::json rows = nlohmann::json::array();
  int search = 0, weight = 0;
  for (const InstanceEval& e : eval.instances) {
    if (!e.has_result || e.adds_m * 1000 < a.min_adds_mm) continue;
    MCPOSE_ASSIGN_OR_RETURN(Frame frame, dataset->LoadFrame(e.key));
    if (!meshes.count(e.obj_id)) {
      MCPOSE_ASSIGN_OR_RETURN(Mesh mesh, dataset->LoadMesh(e.obj_id));
      meshes.emplace(e.obj_id, std::move(mesh));
    }
    const Mesh& mesh = meshes.at(e.obj_id);
    std::optional<ColourImage> colour;
    if (o.appearance.enabled && !mesh.appearance.empty()) {
      MCPOSE_ASSIGN_OR_RETURN(colour, dataset->LoadColour(frame));
    }
    std::vector<Detection> boxes;
    for (const Detection& d : detections)
      if (d.scene_id == e.key.scene_id && d.image_id == e.key.image_id && d.obj_id == e.obj_id) boxes.push_back(d);
    const SE3& T_gt = frame.gt[static_cast<size_t>(e.gt_index)].T_cam_obj;
    const PoseResult& est = results[static_cast<size_t>(e.result_index)];  // the row the evaluation scored
    MCPOSE_ASSIGN_OR_RETURN(std::vector<Eigen::Vector3f> points, dataset->LoadEvalPoints(e.obj_id));
    auto m = analysis::WeighMiss(scorer, frame.K, frame.depth, colour ? &*colour : nullptr, mesh, boxes,
                                 est.T_cam_obj, T_gt, a.as_filter);
    if (!m.ok())
      return Status(m.status().code(), dataset->FrameName(e.key) + ": " + m.status().message());
    const double truth_mm = 1000 * AddS(points, m->truth_aligned, T_gt);
    const char* verdict = m->search_failure() ? "search" : "weight";
    (m->search_failure() ? search : weight)++;
    if (m->search_failure()) turns.push_back(m->basin_turn_deg), moves.push_back(m->basin_shift_mm);
    std::printf("%-10s %-24s %9.1f %10.4f %5d %10.4f %5d %12.1f %8s %10s %9s\n",
                (std::to_string(e.key.scene_id) + "/" + std::to_string(e.key.image_id)).c_str(),
                dataset->ObjectName(e.obj_id).c_str(), 1000 * e.adds_m, m->estimate_weight, m->estimate_box,
                m->truth_weight, m->truth_box, truth_mm, verdict,
                m->search_failure() ? step(m->basin_turn_deg).c_str() : "",
                m->search_failure() ? step(m->basin_shift_mm).c_str() : "");
    rows.push_back({{"scene_id", e.key.scene_id}, {"im_id", e.key.image_id}, {"obj_id", e.obj_id},
                    {"adds_mm", 1000 * e.adds_m}, {"estimate_weight", m->estimate_weight},
                    {"estimate_box", m->estimate_box}, {"truth_weight", m->truth_weight},
                    {"truth_box", m->truth_box}, {"truth_aligned_adds_mm", truth_mm}, {"failure", verdict},
                    {"colour", colour.has_value()}});
    if (m->search_failure()) {  // JSON has no infinity: null where no step reaches the estimate
      const auto value = [](double v) { return std::isinf(v) ? nlohmann::json() : nlohmann::json(v); };
      rows.back()["basin_turn_deg"] = value(m->basin_turn_deg);
      rows.back()["basin_shift_mm"] = value(m->basin_shift_mm);
    }
  }
  std::printf("%d answers: %d search failures, %d weight failures\n", search + weight, search, weight);
  if (!turns.empty()) {
    const auto median = [](std::vector<double> v) {
      std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
      return v[v.size() / 2];
    };
    std::printf("search failures' basin, median: %s deg, %s mm\n", step(median(turns)).c_str(),
                step(median(moves)).c_str());
  }
  if (!a.json.empty()) {
    const nlohmann::json doc = {{"min_adds_mm", a.min_adds_mm}, {"as_filter", a.as_filter}, {"search_failures", search},
                                {"weight_failures", weight}, {"misses", rows}};
    MCPOSE_RETURN_IF_ERROR(io::WriteFileAtomic(a.json, doc.dump(1) + "\n"));
  }
  return Status::Ok();
}

}  // namespace

void AddMissesCommand(CLI::App& app, Status* status) {
  auto args = std::make_shared<MissesArgs>();
  CLI::App* cmd = app.add_subcommand(
      "misses",
      "For each answer far from the truth: whether the truth (aligned to the depth) weighs more than the answer "
      "at full resolution (the search missed it) or not (the weight prefers the wrong pose)");
  cmd->add_option("--dataset", args->dataset, "Dataset root (YCB-Video native or BOP layout)")->required();
  cmd->add_option("--split", args->split, "BOP split folder")->capture_default_str();
  cmd->add_option("--models", args->models, "Models folder the estimate used (its colour)");
  cmd->add_option("--detections", args->detections, "The boxes the estimate was given (BOP JSON)")->required();
  cmd->add_option("--results", args->results, "The estimate's results CSV")->required();
  cmd->add_option("--scene", args->scene, "Only this scene (video)");
  cmd->add_option("--min-adds-mm", args->min_adds_mm, "Answers with at least this ADD-S, mm")->capture_default_str();
  cmd->add_flag("--as-filter", args->as_filter,
                "Weigh as the filter does (its level of detail and pixel stride), not at full resolution");
  AddEstimatorFlags(cmd, kWeightOptions | kEngineOptions | kAppearanceOptions | kRefineOptions,
                         &args->flags);
  cmd->add_option("--json", args->json, "Also write each answer's weights and verdict as JSON");
  cmd->callback([args, status] { *status = RunMisses(*args); });
}

}  // namespace mcpose::tools

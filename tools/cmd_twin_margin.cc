// mcpose-tools twin-margin: per object, how surely the twin-resolving weight ranks the truth
// above its wrong turns (analysis/twin_margin.h).
#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "mcpose/analysis/twin_margin.h"
#include "mcpose/analysis/visible_instances.h"
#include "cli/common.h"
#include "mcpose/io_util.h"
#include "mcpose/dataset.h"
#include "mcpose/eval.h"
#include "mcpose/results.h"
#include "tools.h"

namespace mcpose::tools {

using cli::CheckWritable;

namespace {

struct TwinMarginArgs {
  std::string dataset, split = "test", models, json, results;
  std::vector<int> scenes;  // empty: every real scene
  bool synthetic = false;
  double right_mm = 20, wrong_mm = 40;
  EstimatorFlags flags;
  analysis::TwinMarginOptions margin;
};

struct Tally {
  int instances = 0, with_twins = 0, right = 0, depth_right = 0, colour_right = 0;
  double margin = 0, colour_margin = 0, pixels = 0;
};

Status RunTwinMargin(TwinMarginArgs& a) {
  MCPOSE_RETURN_IF_ERROR(a.flags.Finish());
  a.margin.right_m = a.right_mm / 1000, a.margin.wrong_m = a.wrong_mm / 1000;
  std::string error;
  if (!a.margin.IsValid(&error)) return InvalidArgument("invalid margin options: " + error);
  MCPOSE_RETURN_IF_ERROR(cli::CheckOutputsDistinct({{"--results", a.results}}, {{"--json", a.json}}));
  if (!a.json.empty()) MCPOSE_RETURN_IF_ERROR(CheckWritable(a.json));
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<Dataset> dataset, Dataset::Open(a.dataset, a.split, a.models));
  MCPOSE_RETURN_IF_ERROR(cli::CheckOutputsOutsideDataset(*dataset, {{"--json", a.json}}));
  analysis::Scorer context(a.flags.options);
  // With --results: each answer of an (image, class), the highest-scored row.
  std::map<std::tuple<int, int, int>, SE3> answers;
  if (!a.results.empty()) {
    MCPOSE_ASSIGN_OR_RETURN(std::vector<PoseResult> results, ReadResultsCsv(a.results));
    std::map<std::tuple<int, int, int>, double> score;
    for (const PoseResult& r : results) {
      const auto key = std::make_tuple(r.scene_id, r.im_id, r.obj_id);
      if (!score.count(key) || r.score > score[key]) score[key] = r.score, answers[key] = r.T_cam_obj;
    }
    std::printf("%-10s %-24s %10s %10s %10s %10s %10s %10s\n", "scene/im", "object", "answer mm", "nearest mm",
                "nearest w", "answer w", "best w", "best mm");
  }
  const std::set<int> symmetric = YcbvSymmetricObjectIds();
  std::map<int, Tally> tally;
  nlohmann::json rows = nlohmann::json::array();
  const auto visit = [&](const analysis::VisibleInstance& v) -> Status {
    const int scene = v.frame.key.scene_id;
    if (scene == kSyntheticScene ? !a.synthetic
                                 : !a.scenes.empty() && std::find(a.scenes.begin(), a.scenes.end(), scene) == a.scenes.end())
      return Status::Ok();
    std::optional<ColourImage> colour;
    if (a.flags.options.appearance.enabled && !v.mesh.appearance.empty()) {
      MCPOSE_ASSIGN_OR_RETURN(colour, dataset->LoadColour(v.frame));
    }
    Detection box = v.tight;
    box.score = 1;
    MCPOSE_ASSIGN_OR_RETURN(analysis::TwinMargin m,
                            analysis::MeasureTwinMargin(context, v.frame.K, v.frame.depth, colour ? &*colour : nullptr,
                                                        v.mesh, box, v.gt.T_cam_obj, v.points,
                                                        symmetric.count(v.gt.obj_id) > 0, a.margin));
    if (const auto it = answers.find({scene, v.frame.key.image_id, v.gt.obj_id}); it != answers.end()) {
      const bool sym = symmetric.count(v.gt.obj_id) > 0;
      const std::vector<Eigen::Vector3f> pts(v.points.begin(), v.points.end());
      const double e = sym ? AddS(pts, it->second, v.gt.T_cam_obj) : Add(pts, it->second, v.gt.T_cam_obj);
      if (e >= a.margin.wrong_m) {
        MCPOSE_ASSIGN_OR_RETURN(analysis::TwinReach r,
                                analysis::MeasureTwinReach(context, v.frame.K, v.frame.depth,
                                                           colour ? &*colour : nullptr, v.mesh, box, it->second,
                                                           v.gt.T_cam_obj, v.points, sym));
        std::printf("%-10s %-24s %10.1f %10.1f %10.4f %10.4f %10.4f %10.1f\n",
                    (std::to_string(scene) + "/" + std::to_string(v.frame.key.image_id)).c_str(),
                    dataset->ObjectName(v.gt.obj_id).c_str(), 1000 * e, 1000 * r.nearest_m, r.nearest_weight,
                    r.estimate_weight, r.best_weight, 1000 * r.best_m);
      }
    }
    Tally& t = tally[v.gt.obj_id];
    ++t.instances;
    rows.push_back({{"scene_id", scene}, {"im_id", v.frame.key.image_id}, {"obj_id", v.gt.obj_id},
                    {"colour", m.colour}, {"wrong_candidates", m.wrong}, {"margin", m.margin},
                    {"depth_margin", m.depth_margin}, {"colour_margin", m.colour_margin},
                    {"colour_pixels", m.colour_pixels}});
    if (m.wrong == 0) return Status::Ok();
    ++t.with_twins;
    t.right += m.margin > 0, t.depth_right += m.depth_margin > 0, t.colour_right += m.colour_margin > 0;
    t.margin += m.margin, t.colour_margin += m.colour_margin, t.pixels += m.colour_pixels;
    return Status::Ok();
  };
  MCPOSE_RETURN_IF_ERROR(analysis::ForEachVisibleInstance(*dataset, !a.synthetic, visit, &PrintFrameProgress));
  std::printf("Twin candidates of each visible ground-truth instance (its turns, aligned to the depth), weighed at\n"
              "full resolution in its visible-mask box: right within %.0f mm ADD(-S) of the truth, wrong beyond\n"
              "%.0f mm. 'decided': instances whose best right candidate outweighs every wrong one, by the whole\n"
              "weight, its depth part, its colour agreement; margins are means of best right - best wrong.\n",
              1000 * a.margin.right_m, 1000 * a.margin.wrong_m);
  std::printf("%-24s %5s %6s | %8s %8s %8s | %10s %10s %8s\n", "object", "inst", "twins", "decided", "depth",
              "colour", "margin", "col margin", "pixels");
  Tally all;
  auto line = [](const std::string& name, const Tally& t) {
    const double n = std::max(t.with_twins, 1);
    std::printf("%-24s %5d %6d | %7.1f%% %7.1f%% %7.1f%% | %10.4f %10.4f %8.0f\n", name.c_str(), t.instances,
                t.with_twins, 100 * t.right / n, 100 * t.depth_right / n, 100 * t.colour_right / n, t.margin / n,
                t.colour_margin / n, t.pixels / n);
  };
  for (const auto& [obj, t] : tally) {
    line(dataset->ObjectName(obj), t);
    all.instances += t.instances, all.with_twins += t.with_twins, all.right += t.right;
    all.depth_right += t.depth_right, all.colour_right += t.colour_right;
    all.margin += t.margin, all.colour_margin += t.colour_margin, all.pixels += t.pixels;
  }
  line("ALL", all);
  if (!a.json.empty()) {
    const nlohmann::json doc = {{"right_m", a.margin.right_m}, {"wrong_m", a.margin.wrong_m}, {"instances", rows}};
    MCPOSE_RETURN_IF_ERROR(io::WriteFileAtomic(a.json, doc.dump(1) + "\n"));
  }
  return Status::Ok();
}

}  // namespace

void AddTwinMarginCommand(CLI::App& app, Status* status) {
  auto args = std::make_shared<TwinMarginArgs>();
  CLI::App* cmd = app.add_subcommand(
      "twin-margin",
      "How surely the weight that resolves twins ranks each ground-truth pose above its wrong turns (both aligned "
      "to the depth, at full resolution): the colour term's discrimination, without the search");
  cmd->add_option("--dataset", args->dataset, "Dataset root (YCB-Video native or BOP layout)")->required();
  cmd->add_option("--split", args->split, "BOP split folder")->capture_default_str();
  cmd->add_option("--models", args->models, "Models folder to read meshes (and their colour) from");
  cmd->add_option("--scene", args->scenes, "Only these scenes (videos); default every real one");
  cmd->add_flag("--synthetic", args->synthetic, "Also the synthetic frames (YCB-Video data_syn)");
  cmd->add_option("--right-mm", args->right_mm, "A candidate within this ADD(-S) of the truth is right, mm")
      ->capture_default_str();
  cmd->add_option("--wrong-mm", args->wrong_mm, "A candidate beyond this ADD(-S) is wrong, mm")
      ->capture_default_str();
  AddEstimatorFlags(cmd, kWeightOptions | kEngineOptions | kAppearanceOptions | kRefineOptions,
                         &args->flags);
  cmd->add_option("--json", args->json, "Also write each instance's margins as JSON");
  cmd->add_option("--results", args->results,
                  "Also, for each answer of this results CSV beyond --wrong-mm: its twin candidates (aligned), the "
                  "one nearest the truth and whether it outweighs the answer");
  cmd->callback([args, status] { *status = RunTwinMargin(*args); });
}

}  // namespace mcpose::tools

#include <cstdio>
#include <algorithm>
#include <map>
#include <optional>
#include <memory>

#include <nlohmann/json.hpp>

#include "mcpose/analysis/turn_profile.h"
#include "cli/common.h"
#include "mcpose/io_util.h"
#include "tools.h"
#include "mcpose/dataset.h"
#include "mcpose/detection.h"
#include "mcpose/eval.h"

namespace mcpose::tools {

using cli::CheckWritable;

namespace {

struct TurnProfileArgs {
  std::string dataset, split = "test", models, detections, json;
  int obj_id = 0;
  EstimatorFlags flags;
  analysis::TurnProfileOptions turn;
};

Status RunTurnProfile(TurnProfileArgs& a) {
  MCPOSE_RETURN_IF_ERROR(a.flags.Finish());
  const EstimatorOptions& o = a.flags.options;
  std::string error;
  if (!a.turn.IsValid(&error)) return InvalidArgument("invalid turn options: " + error);
  if (!a.json.empty()) MCPOSE_RETURN_IF_ERROR(CheckWritable(a.json));
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<Dataset> dataset, Dataset::Open(a.dataset, a.split, a.models));
  MCPOSE_RETURN_IF_ERROR(cli::CheckOutputsOutsideDataset(*dataset, {{"--json", a.json}}));
  MCPOSE_ASSIGN_OR_RETURN(std::vector<Detection> detections, ReadDetectionsJson(a.detections));
  MCPOSE_ASSIGN_OR_RETURN(Mesh mesh, dataset->LoadMesh(a.obj_id));
  // The images with boxes of the class, in order.
  std::map<FrameKey, std::vector<Detection>> boxes;
  for (const Detection& d : detections)
    if (d.obj_id == a.obj_id) boxes[FrameKey{d.scene_id, d.image_id}].push_back(d);
  if (boxes.empty())
    return InvalidArgument(a.detections + ": no box of obj_id " + std::to_string(a.obj_id));

  const int axis = a.turn.axis >= 0 ? a.turn.axis : analysis::TurnAxis(mesh);
  std::printf("turn profile of %s about model axis %c, %g deg steps, the truth within %g deg; engine %s, "
              "LOD %.2f px, pixel stride %d\n",
              dataset->ObjectName(a.obj_id).c_str(), "xyz"[axis], a.turn.step_deg, a.turn.near_deg,
              RasterBackendName(o.engine.backend), o.engine.lod_error_px, o.engine.pixel_stride);
  std::printf("%-12s %9s %6s %8s %9s %9s %7s | %8s %8s %8s\n", "scene/image", "triangles", "stride", "truth",
              "jitter", "range", "beaten", "flip x", "flip y", "flip z");
  nlohmann::json instances = nlohmann::json::array();
  double sum_jitter = 0, sum_range = 0, sum_beaten = 0;
  int n = 0;
  for (const auto& [key, candidates] : boxes) {
    MCPOSE_ASSIGN_OR_RETURN(Frame frame, dataset->LoadFrame(key));
    std::optional<ColourImage> colour;
    if (o.appearance.enabled && !mesh.appearance.empty()) {
      MCPOSE_ASSIGN_OR_RETURN(colour, dataset->LoadColour(frame));
    }
    for (const GtInstance& gt : frame.gt) {
      if (gt.obj_id != a.obj_id) continue;
      MCPOSE_ASSIGN_OR_RETURN(MaskImage mask, dataset->LoadVisibleMask(key, gt));
      Detection tight;
      if (MaskBox(mask, &tight) == 0) continue;  // not visible
      const Detection* box = &candidates[0];     // the box that overlaps the instance most
      for (const Detection& d : candidates)
        if (BoxIou(d, tight) > BoxIou(*box, tight)) box = &d;
      if (BoxIou(*box, tight) == 0) continue;  // a distractor box elsewhere
      auto profile = analysis::ProfileTurns(frame.K, frame.depth, colour ? &*colour : nullptr, mesh, *box,
                                            gt.T_cam_obj, o, a.turn);
      if (!profile.ok())
        return Status(profile.status().code(), "scene " + std::to_string(key.scene_id) + " image " +
                                                   std::to_string(key.image_id) + ": " + profile.status().message());
      const analysis::TurnProfileStats& s = profile->stats;
      std::printf("%-12s %9d %6d %8.5f %9.5f %9.5f %6.1f%% | %8.5f %8.5f %8.5f%s\n",
                  (std::to_string(key.scene_id) + "/" + std::to_string(key.image_id)).c_str(), profile->triangles,
                  profile->stride, s.truth, s.jitter, s.range, 100 * s.beaten, profile->flip_weight[0],
                  profile->flip_weight[1], profile->flip_weight[2], profile->colour ? "  colour" : "");
      sum_jitter += s.jitter, sum_range += s.range, sum_beaten += s.beaten, ++n;
      instances.push_back({{"scene_id", key.scene_id}, {"im_id", key.image_id}, {"gt_index", gt.gt_index},
                           {"box", {box->x, box->y, box->w, box->h}}, {"triangles", profile->triangles},
                           {"stride", profile->stride}, {"angle_deg", profile->angle_deg},
                           {"weight", profile->weight}, {"truth", s.truth}, {"jitter", s.jitter},
                           {"range", s.range}, {"beaten", s.beaten}, {"colour", profile->colour},
                           {"flip_weight", profile->flip_weight}});
    }
  }
  if (n == 0)
    return InvalidArgument(a.detections + ": no box of obj_id " + std::to_string(a.obj_id) +
                           " overlaps a visible ground-truth instance of it");
  std::printf("%-12s %9s %6s %8s %9.5f %9.5f %6.1f%%\n", "mean", "", "", "", sum_jitter / n, sum_range / n,
              100 * sum_beaten / n);
  if (!a.json.empty()) {
    nlohmann::json doc = {{"obj_id", a.obj_id}, {"name", dataset->ObjectName(a.obj_id)}, {"axis", axis},
                          {"step_deg", a.turn.step_deg}, {"near_deg", a.turn.near_deg},
                          {"engine", RasterBackendName(o.engine.backend)}, {"lod_px", o.engine.lod_error_px},
                          {"pixel_stride", o.engine.pixel_stride}, {"max_grid_pixels", o.engine.max_grid_pixels},
                          {"mean_jitter", sum_jitter / n}, {"mean_range", sum_range / n},
                          {"mean_beaten", sum_beaten / n}, {"instances", instances}};
    MCPOSE_RETURN_IF_ERROR(io::WriteFileAtomic(a.json, doc.dump(1) + "\n"));
  }
  return Status::Ok();
}

}  // namespace

void AddTurnProfileCommand(CLI::App& app, Status* status) {
  auto args = std::make_shared<TurnProfileArgs>();
  CLI::App* cmd = app.add_subcommand(
      "turn-profile",
      "The engine's weight of each ground-truth pose turned about a model axis: how much an engine option's "
      "turn-to-turn jitter hides the weight that tells the right turn");
  cmd->add_option("--dataset", args->dataset, "Dataset root (YCB-Video native or BOP layout)")->required();
  cmd->add_option("--split", args->split, "BOP split folder")->capture_default_str();
  cmd->add_option("--detections", args->detections, "BOP default-detections JSON: each instance is scored in "
                                                   "its class's box that overlaps it most")->required();
  cmd->add_option("--obj", args->obj_id, "obj_id of the class to profile")->required();
  cmd->add_option("--axis", args->turn.axis, "Model axis 0, 1, 2; -1: the one whose extent differs most from the "
                                             "other two (a can's axis)")->capture_default_str();
  cmd->add_option("--step-deg", args->turn.step_deg, "Turn step, degrees (divides 360, at most 45)")->capture_default_str();
  cmd->add_option("--near-deg", args->turn.near_deg, "Turns within this of the truth count as the truth")->capture_default_str();
  cmd->add_option("--models", args->models, "Models folder to read meshes (and their colour) from");
  AddEstimatorFlags(cmd, kWeightOptions | kEngineOptions | kAppearanceOptions, &args->flags);
  cmd->add_option("--json", args->json, "Also write each instance's profile (angles, weights) and the statistics");
  cmd->callback([args, status] { *status = RunTurnProfile(*args); });
}

}  // namespace mcpose::tools

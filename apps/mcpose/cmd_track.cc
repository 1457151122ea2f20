#include <algorithm>
#include <charconv>
#include <cstdint>
#include <limits>
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <set>

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "cli/common.h"
#include "io/io_util.h"
#include "commands.h"
#include "engine/pipeline.h"
#include "io/options_json.h"
#include "mcpose/dataset.h"
#include "mcpose/detection.h"
#include "mcpose/eval.h"
#include "mcpose/results.h"
#include "mcpose/tracker.h"

namespace mcpose::cli {

namespace {

struct TrackArgs {
  std::string dataset, split = "test", models, detections, out, out_json, frames;
  int video = -1;
  double min_score = 0;
  bool quiet = false;
  EstimatorFlags flags;
  TrackerOptions tracker;
};

// "A-B" (inclusive) or "A"; empty: every frame. Frame numbers are decimal digits; one past the
// largest int (any frame past a video's end) means "to the end".
Status ParseFrameRange(const std::string& text, int* first, int* last) {
  *first = 0, *last = std::numeric_limits<int>::max();
  if (text.empty()) return Status::Ok();
  const auto number = [](const std::string& digits, int* value) {
    if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos) return false;
    uint64_t v = 0;
    const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v);
    const uint64_t max = static_cast<uint64_t>(std::numeric_limits<int>::max());
    *value = static_cast<int>(ec == std::errc::result_out_of_range || v > max ? max : v);
    return ec == std::errc() || ec == std::errc::result_out_of_range;
  };
  const size_t dash = text.find('-');
  const bool ok = number(text.substr(0, dash), first) &&
                  (dash == std::string::npos ? (*last = *first, true) : number(text.substr(dash + 1), last));
  if (!ok) return InvalidArgument("--frames must be A-B or A (frame numbers), got '" + text + "'");
  if (*last < *first) return InvalidArgument("--frames must be A-B with A <= B, got '" + text + "'");
  return Status::Ok();
}

Status RunTrack(TrackArgs& a) {
  MCPOSE_RETURN_IF_ERROR(a.flags.Finish());
  a.tracker.estimator = a.flags.options;
  std::string error;
  if (!a.tracker.IsValid(&error)) return InvalidArgument("invalid tracker options: " + error);
  int first = 0, last = 0;
  MCPOSE_RETURN_IF_ERROR(ParseFrameRange(a.frames, &first, &last));
  MCPOSE_RETURN_IF_ERROR(CheckOutputsDistinct({{"--detections", a.detections}}, {{"--out", a.out}, {"--out-json", a.out_json}}));
  MCPOSE_RETURN_IF_ERROR(CheckWritable(a.out));
  if (!a.out_json.empty()) MCPOSE_RETURN_IF_ERROR(CheckWritable(a.out_json));
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<Dataset> dataset, Dataset::Open(a.dataset, a.split, a.models));
  MCPOSE_RETURN_IF_ERROR(CheckOutputsOutsideDataset(*dataset, {{"--out", a.out}, {"--out-json", a.out_json}}));

  // ---- The frames of the video, and each frame's boxes --------------------------------------
  std::vector<FrameKey> frames;
  for (const FrameKey& k : dataset->Frames())
    if (k.scene_id == a.video && k.image_id >= first && k.image_id <= last) frames.push_back(k);
  if (frames.empty())
    return NotFound(a.dataset + ": no frame of video " + std::to_string(a.video) + " in the range '" + a.frames + "'");
  std::map<FrameKey, std::map<int, std::vector<Detection>>> boxes;
  if (!a.detections.empty()) {
    MCPOSE_ASSIGN_OR_RETURN(std::vector<Detection> dets, ReadDetectionsJson(a.detections));
    MCPOSE_RETURN_IF_ERROR(KeepScoresAtLeast(a.min_score, a.detections, &dets));
    MCPOSE_RETURN_IF_ERROR(CheckDetectionsAgainstDataset(*dataset, dets, a.detections));
    for (const Detection& d : dets) boxes[FrameKey{d.scene_id, d.image_id}][d.obj_id].push_back(d);
  } else {  // tight boxes of the ground-truth visible masks
    for (const FrameKey& k : frames) {
      MCPOSE_ASSIGN_OR_RETURN(Frame f, dataset->LoadFrame(k));
      for (const GtInstance& gt : f.gt) {
        MCPOSE_ASSIGN_OR_RETURN(MaskImage mask, dataset->LoadVisibleMask(k, gt));
        Detection d{k.scene_id, k.image_id, gt.obj_id, 1.0};
        if (MaskBox(mask, &d) > 0) boxes[k][gt.obj_id].push_back(d);
      }
    }
  }
  const std::vector<int> known = dataset->ObjectIds();
  std::map<int, Mesh> meshes;
  for (const FrameKey& k : frames)
    for (const auto& [obj_id, dets] : boxes[k]) {
      if (!std::binary_search(known.begin(), known.end(), obj_id))  // boxes from the ground truth
        return InvalidArgument(dataset->FrameName(k) + ": the ground truth names obj_id " + std::to_string(obj_id) +
                               ", which has no model in " + dataset->models_dir());
      if (!meshes.count(obj_id)) {
        MCPOSE_ASSIGN_OR_RETURN(Mesh m, dataset->LoadMesh(obj_id));
        meshes.emplace(obj_id, std::move(m));
      }
    }
  if (meshes.empty()) return InvalidArgument("no box of video " + std::to_string(a.video) + " in the frames asked for");

  // ---- Track, frame by frame --------------------------------------------------------------
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<Tracker> tracker, Tracker::Create(a.tracker));
  using Clock = std::chrono::steady_clock;
  std::vector<PoseResult> rows;
  nlohmann::json steps = nlohmann::json::array();
  std::map<int, const Mesh*> mesh_of;
  for (const auto& [obj_id, mesh] : meshes) mesh_of.emplace(obj_id, &mesh);
  for (const FrameKey& k : frames) {
    const auto frame_start = Clock::now();
    MCPOSE_ASSIGN_OR_RETURN(Frame frame, dataset->LoadFrame(k));
    StatusOr<std::vector<TrackStep>> frame_steps =
        TrackFrame(*tracker, frame, mesh_of, boxes[k], [&] { return dataset->LoadColour(frame); });
    if (!frame_steps.ok())
      return Status(frame_steps.status().code(), dataset->FrameName(k) + ": " + frame_steps.status().message());
    const size_t first_row = rows.size();
    for (const TrackStep& step : *frame_steps) {
      const int obj_id = step.obj_id;
      PoseResult row;
      row.scene_id = k.scene_id, row.im_id = k.image_id, row.obj_id = obj_id;
      row.score = step.weight;
      row.T_cam_obj = step.T_cam_obj;
      rows.push_back(row);
      nlohmann::json R = nlohmann::json::array(), t = nlohmann::json::array();
      for (int i = 0; i < 9; ++i) R.push_back(step.T_cam_obj.R(i / 3, i % 3));
      for (int i = 0; i < 3; ++i) t.push_back(1000 * step.T_cam_obj.t(i));
      steps.push_back({{"scene_id", k.scene_id}, {"im_id", k.image_id}, {"obj_id", obj_id},
                       {"name", dataset->ObjectName(obj_id)}, {"initialised", step.initialised},
                       {"lost", step.lost}, {"weight", step.weight}, {"fit", step.fit}, {"visible", step.visible}, {"iterations", step.iterations},
                       {"box", {step.box.x, step.box.y, step.box.w, step.box.h}}, {"ms", step.ms},
                       {"R", R}, {"t_mm", t}});
      if (!a.quiet)
        spdlog::info("{} obj {:2d} {:<24} {} w {:.3f} fit {:.3f} vis {:.2f} it {:2d} {:.1f} ms", dataset->FrameName(k), obj_id,
                     dataset->ObjectName(obj_id),
                     step.lost ? (step.initialised ? "lost, restarted" : "lost") : step.initialised ? "started" : "tracked",
                     step.weight, step.fit, step.visible, step.iterations, step.ms);
    }
    const double frame_s = std::chrono::duration<double>(Clock::now() - frame_start).count();
    for (size_t r = first_row; r < rows.size(); ++r) rows[r].time_s = frame_s;
  }

  // ---- Outputs, written only after everything succeeded -------------------------------------
  if (!a.out_json.empty()) {
    nlohmann::json doc = {{"dataset", a.dataset}, {"video", a.video}, {"options", io::TrackerOptionsToJson(a.tracker)}, {"steps", steps}};
    MCPOSE_RETURN_IF_ERROR(io::WriteFileAtomic(a.out_json, doc.dump(1) + "\n"));
  }
  std::sort(rows.begin(), rows.end(), [](const PoseResult& x, const PoseResult& y) {
    return std::tie(x.scene_id, x.im_id, x.obj_id) < std::tie(y.scene_id, y.im_id, y.obj_id);
  });
  if (Status written = WriteResultsCsv(a.out, rows); !written.ok()) {
    RemoveOutput(a.out_json);  // no half of the outputs is left behind
    return written;
  }
  return Status::Ok();
}

}  // namespace

void AddTrackCommand(CLI::App& app, Status* status) {
  auto args = std::make_shared<TrackArgs>();
  TrackerOptions& t = args->tracker;
  CLI::App* cmd = app.add_subcommand(
      "track", "Follow the objects through the frames of one video: each frame starts from the last one's samples");
  cmd->add_option("--dataset", args->dataset, "Dataset root (YCB-Video native or BOP layout)")->required();
  cmd->add_option("--split", args->split, "BOP split folder")->capture_default_str();
  cmd->add_option("--models", args->models, "Models folder to read meshes (and their colour) from");
  cmd->add_option("--video", args->video, "scene_id of the video")->required();
  cmd->add_option("--frames", args->frames, "Frames A-B (inclusive) or A; default: every frame of the video");
  cmd->add_option("--detections", args->detections,
                  "BOP detections JSON that starts (and restarts lost) tracks; default: tight boxes of the ground-truth "
                  "visible masks");
  cmd->add_option("--min-score", args->min_score, "Leave out boxes of --detections whose score is below this (default 0)")
      ->capture_default_str();
  cmd->add_option("--out", args->out, "Results CSV, one row per (frame, object)")->required();
  cmd->add_option("--out-json", args->out_json, "Per (frame, object): started, tracked or lost, weight, fit, iterations, box, time");
  AddTrackerFlags(cmd, &t);
  AddEstimatorFlags(cmd, kAllEstimatorFlags & ~kInstanceFlags, &args->flags);
  cmd->add_flag("-q,--quiet", args->quiet, "No progress output");
  cmd->callback([args, status] { *status = RunTrack(*args); });
}

}  // namespace mcpose::cli

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

#include <spdlog/spdlog.h>

#include "cli/common.h"
#include "mcpose/io_util.h"
#include "commands.h"
#include "mcpose/estimate_detail.h"
#include "mcpose/run.h"
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
  TrackRun run;
  run.video = a.video;
  MCPOSE_RETURN_IF_ERROR(ParseFrameRange(a.frames, &run.first_frame, &run.last_frame));
  MCPOSE_RETURN_IF_ERROR(CheckOutputsDistinct({{"--detections", a.detections}}, {{"--out", a.out}, {"--out-json", a.out_json}}));
  MCPOSE_RETURN_IF_ERROR(CheckWritable(a.out));
  if (!a.out_json.empty()) MCPOSE_RETURN_IF_ERROR(CheckWritable(a.out_json));
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<Dataset> dataset, Dataset::Open(a.dataset, a.split, a.models));
  MCPOSE_RETURN_IF_ERROR(CheckOutputsOutsideDataset(*dataset, {{"--out", a.out}, {"--out-json", a.out_json}}));
  std::vector<Detection> detections;
  if (!a.detections.empty()) {
    MCPOSE_ASSIGN_OR_RETURN(detections, ReadDetectionsJson(a.detections));
    MCPOSE_RETURN_IF_ERROR(KeepScoresAtLeast(a.min_score, a.detections, &detections));
    run.detections = &detections;
    run.detections_source = a.detections;
  }
  const auto progress = [&](const TrackRecord& r) {
    if (a.quiet) return;
    const TrackStep& step = r.step;
    spdlog::info("{} obj {:2d} {:<24} {} w {:.3f} fit {:.3f} vis {:.2f} it {:2d} {:.1f} ms", dataset->FrameName(r.key),
                 step.obj_id, r.name,
                 step.lost ? (step.initialised ? "lost, restarted" : "lost") : step.initialised ? "started" : "tracked",
                 step.weight, step.fit, step.visible, step.iterations, step.ms);
  };
  MCPOSE_ASSIGN_OR_RETURN(const TrackReport report, RunTracking(*dataset, run, a.tracker, progress));

  // ---- Outputs, written only after everything succeeded -------------------------------------
  if (!a.out_json.empty())
    MCPOSE_RETURN_IF_ERROR(
        io::WriteFileAtomic(a.out_json, ::mcpose::report::TrackDetailJson(report, a.tracker, a.dataset, a.video).dump(1) + "\n"));
  if (Status written = WriteResultsCsv(a.out, report.results); !written.ok()) {
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
  AddEstimatorFlags(cmd, kAllOptions & ~kInstanceOptions, &args->flags);
  cmd->add_flag("-q,--quiet", args->quiet, "No progress output");
  cmd->callback([args, status] { *status = RunTrack(*args); });
}

}  // namespace mcpose::cli

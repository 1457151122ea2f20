// RunTracking (mcpose/run.h): the tracking job of `mcpose track` on a dataset's video.
#include <algorithm>
#include <chrono>
#include <limits>
#include <map>
#include <memory>
#include <tuple>

#include "mcpose/eval.h"
#include "mcpose/run.h"
#include "mcpose/tracker.h"

namespace mcpose {

StatusOr<TrackReport> RunTracking(const Dataset& dataset, const TrackRun& run, const TrackerOptions& options,
                                  const std::function<void(const TrackRecord&)>& progress) {
  std::string error;
  if (!options.IsValid(&error)) return InvalidArgument("invalid tracker options: " + error);
  if (run.last_frame < run.first_frame) return InvalidArgument("the last frame lies before the first");

  // ---- The frames of the video, and each frame's boxes --------------------------------------
  std::vector<FrameKey> frames;
  for (const FrameKey& k : dataset.Frames())
    if (k.scene_id == run.video && k.image_id >= run.first_frame && k.image_id <= run.last_frame) frames.push_back(k);
  if (frames.empty())
    return NotFound(dataset.root() + ": no frame of video " + std::to_string(run.video) + " in frames " +
                    std::to_string(run.first_frame) + "-" +
                    (run.last_frame == std::numeric_limits<int>::max() ? std::string("end")
                                                                       : std::to_string(run.last_frame)));
  std::map<FrameKey, std::map<int, std::vector<Detection>>> boxes;
  if (run.detections != nullptr) {
    MCPOSE_RETURN_IF_ERROR(CheckDetectionsAgainstDataset(dataset, *run.detections, run.detections_source));
    for (const Detection& d : *run.detections) boxes[FrameKey{d.scene_id, d.image_id}][d.obj_id].push_back(d);
  } else {  // tight boxes of the ground-truth visible masks
    for (const FrameKey& k : frames) {
      MCPOSE_ASSIGN_OR_RETURN(Frame f, dataset.LoadFrame(k));
      for (const GtInstance& gt : f.gt) {
        MCPOSE_ASSIGN_OR_RETURN(MaskImage mask, dataset.LoadVisibleMask(k, gt));
        Detection d{k.scene_id, k.image_id, gt.obj_id, 1.0};
        if (MaskBox(mask, &d) > 0) boxes[k][gt.obj_id].push_back(d);
      }
    }
  }
  const std::vector<int> known = dataset.ObjectIds();
  std::map<int, Mesh> meshes;
  for (const FrameKey& k : frames)
    for (const auto& [obj_id, dets] : boxes[k]) {
      if (!std::binary_search(known.begin(), known.end(), obj_id))  // boxes from the ground truth
        return InvalidArgument(dataset.FrameName(k) + ": the ground truth names obj_id " + std::to_string(obj_id) +
                               ", which has no model in " + dataset.models_dir());
      if (!meshes.count(obj_id)) {
        MCPOSE_ASSIGN_OR_RETURN(Mesh m, dataset.LoadMesh(obj_id));
        meshes.emplace(obj_id, std::move(m));
      }
    }
  if (meshes.empty()) return InvalidArgument("no box of video " + std::to_string(run.video) + " in the frames asked for");

  // ---- Track, frame by frame --------------------------------------------------------------
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<Tracker> tracker, Tracker::Create(options));
  using Clock = std::chrono::steady_clock;
  TrackReport report;
  std::map<int, const Mesh*> mesh_of;
  for (const auto& [obj_id, mesh] : meshes) mesh_of.emplace(obj_id, &mesh);
  for (const FrameKey& k : frames) {
    const auto frame_start = Clock::now();
    MCPOSE_ASSIGN_OR_RETURN(Frame frame, dataset.LoadFrame(k));
    StatusOr<std::vector<TrackStep>> frame_steps =
        TrackFrame(*tracker, frame, mesh_of, boxes[k], [&] { return dataset.LoadColour(frame); });
    if (!frame_steps.ok())
      return Status(frame_steps.status().code(), dataset.FrameName(k) + ": " + frame_steps.status().message());
    const size_t first_row = report.results.size();
    for (const TrackStep& step : *frame_steps) {
      PoseResult row;
      row.scene_id = k.scene_id, row.im_id = k.image_id, row.obj_id = step.obj_id;
      row.score = step.weight;
      row.T_cam_obj = step.T_cam_obj;
      report.results.push_back(row);
      report.steps.push_back(TrackRecord{k, dataset.ObjectName(step.obj_id), step});
      if (progress) progress(report.steps.back());
    }
    const double frame_s = std::chrono::duration<double>(Clock::now() - frame_start).count();
    for (size_t r = first_row; r < report.results.size(); ++r) report.results[r].time_s = frame_s;
  }
  std::sort(report.results.begin(), report.results.end(), [](const PoseResult& x, const PoseResult& y) {
    return std::tie(x.scene_id, x.im_id, x.obj_id) < std::tie(y.scene_id, y.im_id, y.obj_id);
  });
  return report;
}

}  // namespace mcpose

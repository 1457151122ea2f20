#include "engine/pipeline.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <optional>
#include <set>

#include <spdlog/spdlog.h>

#include "core/rng.h"
#include "engine/box_scorer.h"

namespace mcpose {
namespace {

// True if some box of `dets` holds a pixel with a depth measurement.
bool BoxesHoldDepth(const DepthImage& depth, const std::vector<Detection>& dets) {
  for (const Detection& d : dets) {
    const render::PixelRect r = engine::ClipBox(d.x, d.y, d.w, d.h, depth.width, depth.height);
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x)
        if (depth.at(x, y) > 0.f) return true;
  }
  return false;
}

}  // namespace

uint64_t GroupStreamId(int scene_id, int image_id, int obj_id) {
  return HashCombine(HashCombine(static_cast<uint64_t>(scene_id), static_cast<uint64_t>(image_id)),
                     static_cast<uint64_t>(obj_id));
}

StatusOr<RunReport> RunEstimation(const Dataset& dataset, const std::vector<Detection>& detections,
                                  const std::string& detections_source,
                                  const EstimatorOptions& options, const ProgressFn& progress) {
  using Clock = std::chrono::steady_clock;
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<Estimator> estimator, Estimator::Create(options));

  // ---- Group detections by image and class, checking each against the dataset ------------
  const std::vector<FrameKey> frames = dataset.Frames();
  const std::set<FrameKey> frame_set(frames.begin(), frames.end());
  const std::vector<int> ids = dataset.ObjectIds();
  const std::set<int> id_set(ids.begin(), ids.end());
  std::map<FrameKey, std::map<int, std::vector<Detection>>> groups;
  for (size_t i = 0; i < detections.size(); ++i) {
    const Detection& d = detections[i];
    const std::string where = detections_source + ": detection " + std::to_string(i) + " (scene_id " +
                              std::to_string(d.scene_id) + ", image_id " + std::to_string(d.image_id) + ")";
    const FrameKey key{d.scene_id, d.image_id};
    if (!frame_set.count(key)) return NotFound(where + ": no such image in " + dataset.root());
    if (!id_set.count(d.obj_id))
      return InvalidArgument(where + ": unknown class (category_id " + std::to_string(d.obj_id) +
                             "); the dataset has no model for it");
    groups[key][d.obj_id].push_back(d);
  }

  // ---- Load what the run needs before estimating anything ---------------------------------
  std::map<int, Mesh> meshes;
  for (auto& [key, by_class] : groups) {
    MCPOSE_ASSIGN_OR_RETURN(Frame frame, dataset.LoadFrame(key));
    for (auto it = by_class.begin(); it != by_class.end();) {
      const auto& [obj_id, dets] = *it;
      for (const Detection& d : dets) {
        if (Status st = engine::CheckBox(d, frame.K); !st.ok())
          return InvalidArgument(detections_source + ": obj_id " + std::to_string(obj_id) + " in scene_id " +
                                 std::to_string(key.scene_id) + ", image_id " + std::to_string(key.image_id) +
                                 ": " + st.message());
      }
      // A class whose boxes hold no depth (all zero or saturated) has nothing to fit: no row.
      if (!BoxesHoldDepth(frame.depth, dets)) {
        spdlog::warn("{}: no valid depth in the {} box(es) of class {} ({}); it gets no result", frame.depth_path,
                     dets.size(), obj_id, dataset.ObjectName(obj_id));
        it = by_class.erase(it);
        continue;
      }
      if (!meshes.count(obj_id)) {
        MCPOSE_ASSIGN_OR_RETURN(Mesh mesh, dataset.LoadMesh(obj_id));
        meshes.emplace(obj_id, std::move(mesh));
      }
      ++it;
    }
  }
  std::erase_if(groups, [](const auto& group) { return group.second.empty(); });
  int total = 0;
  for (const auto& [key, by_class] : groups) total += static_cast<int>(by_class.size());
  std::vector<const Mesh*> mesh_list;
  for (const auto& [obj_id, mesh] : meshes) mesh_list.push_back(&mesh);
  estimator->PrepareMeshes(mesh_list);  // the LOD chains and colour grids, a mesh per raster core

  // ---- Estimate each (image, class) ------------------------------------------------------
  RunReport report;
  int done = 0;
  for (const auto& [key, by_class] : groups) {
    const auto image_start = Clock::now();
    MCPOSE_ASSIGN_OR_RETURN(Frame frame, dataset.LoadFrame(key));
    // The colour image, when some class of the image has a model with colour to compare.
    std::optional<ColourImage> colour;
    bool wants_colour = false;
    for (const auto& [obj_id, dets] : by_class) wants_colour |= !meshes.at(obj_id).appearance.empty();
    if (options.appearance.enabled && wants_colour) {
      MCPOSE_ASSIGN_OR_RETURN(colour, dataset.LoadColour(frame));
    }
    const size_t first_row = report.results.size();
    for (const auto& [obj_id, dets] : by_class) {
      const auto start = Clock::now();
      MCPOSE_ASSIGN_OR_RETURN(
          ObjectEstimate est,
          estimator->Estimate(frame.K, frame.depth, colour ? &*colour : nullptr, meshes.at(obj_id), dets,
                              GroupStreamId(key.scene_id, key.image_id, obj_id)));
      ObjectRecord rec;
      rec.key = key;
      rec.obj_id = obj_id;
      rec.name = dataset.ObjectName(obj_id);
      rec.num_boxes = static_cast<int>(dets.size());
      rec.chosen_box = dets[est.best_box];
      rec.estimate = std::move(est);
      rec.time_s = std::chrono::duration<double>(Clock::now() - start).count();

      PoseResult row;
      row.scene_id = key.scene_id;
      row.im_id = key.image_id;
      row.obj_id = obj_id;
      row.score = rec.estimate.best_weight;
      row.T_cam_obj = rec.estimate.T_cam_obj;
      report.results.push_back(row);
      report.objects.push_back(std::move(rec));
      ++done;
      if (progress) progress(done, total, report.objects.back());
    }
    // BOP's time column: the whole image, the same on each of its rows.
    const double image_s = std::chrono::duration<double>(Clock::now() - image_start).count();
    for (size_t r = first_row; r < report.results.size(); ++r) report.results[r].time_s = image_s;
  }
  return report;
}

}  // namespace mcpose

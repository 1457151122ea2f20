#include "mcpose/run.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <optional>
#include <set>

#include <spdlog/spdlog.h>

#include "mcpose/limits.h"
#include "core/rng.h"
#include "engine/box_scorer.h"
#include "engine/instances.h"

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

bool ImageWantsColour(const EstimatorOptions& options, const std::map<int, std::vector<Detection>>& boxes,
                      const std::map<int, const Mesh*>& meshes) {
  if (!options.appearance.enabled) return false;
  for (const auto& [obj_id, dets] : boxes)
    if (!meshes.at(obj_id)->appearance.empty()) return true;
  return false;
}

StatusOr<ImageEstimate> EstimateImage(Estimator& estimator, const FrameKey& key, const Intrinsics& K,
                                      const DepthImage& depth, const ColourImage* colour,
                                      const std::map<int, std::vector<Detection>>& boxes,
                                      const std::map<int, const Mesh*>& meshes,
                                      const std::function<std::string(int)>& name_of,
                                      const std::function<void(const ObjectRecord&)>& on_object,
                                      const std::map<int, int>* instances_of_class) {
  using Clock = std::chrono::steady_clock;
  const auto image_start = Clock::now();
  const EstimatorOptions& options = estimator.options();
  if (!ImageWantsColour(options, boxes, meshes)) colour = nullptr;
  ImageEstimate out;
  for (const auto& [obj_id, dets] : boxes) {
    const Mesh& mesh = *meshes.at(obj_id);
    const uint64_t stream = GroupStreamId(key.scene_id, key.image_id, obj_id);
    int max_instances = options.max_instances > 0 ? options.max_instances : static_cast<int>(dets.size());
    if (instances_of_class) {
      const auto given = instances_of_class->find(obj_id);
      if (given != instances_of_class->end()) max_instances = std::max(1, given->second);
    }
    // One instance: the filter over all the class's boxes. Then one per further cluster of
    // boxes, unless it explains the pixels of an instance kept before it.
    std::vector<ObjectRecord> kept;
    std::vector<std::vector<int>> kept_pixels;
    const auto estimate = [&](std::span<const Detection> group, uint64_t group_stream,
                              int instance) -> StatusOr<ObjectRecord> {
      const auto start = Clock::now();
      MCPOSE_ASSIGN_OR_RETURN(ObjectEstimate est, estimator.Estimate(K, depth, colour, mesh, group, group_stream));
      ObjectRecord rec;
      rec.key = key;
      rec.obj_id = obj_id;
      rec.instance = instance;
      if (name_of) rec.name = name_of(obj_id);
      rec.num_boxes = static_cast<int>(group.size());
      rec.chosen_box = group[static_cast<size_t>(est.best_box)];
      rec.estimate = std::move(est);
      rec.time_s = std::chrono::duration<double>(Clock::now() - start).count();
      return rec;
    };
    MCPOSE_ASSIGN_OR_RETURN(ObjectRecord first, estimate(dets, stream, 0));
    kept.push_back(std::move(first));
    const std::vector<std::vector<int>> clusters =
        max_instances > 1 && dets.size() > 1 ? engine::ClusterBoxes(dets) : std::vector<std::vector<int>>{};
    if (clusters.size() > 1) {
      const int first_box = kept.front().estimate.best_box;
      kept_pixels.push_back(engine::ExplainedPixels(mesh, kept.front().estimate.T_cam_obj, K, depth,
                                                    options.weight.eps_m));
      for (size_t c = 0; c < clusters.size() && static_cast<int>(kept.size()) < max_instances; ++c) {
        if (std::find(clusters[c].begin(), clusters[c].end(), first_box) != clusters[c].end()) continue;
        std::vector<Detection> group;
        for (int i : clusters[c]) group.push_back(dets[static_cast<size_t>(i)]);
        MCPOSE_ASSIGN_OR_RETURN(ObjectRecord rec,
                                estimate(group, HashCombine(stream, c + 1), static_cast<int>(kept.size())));
        std::vector<int> pixels =
            engine::ExplainedPixels(mesh, rec.estimate.T_cam_obj, K, depth, options.weight.eps_m);
        const bool same = std::any_of(kept_pixels.begin(), kept_pixels.end(), [&](const std::vector<int>& p) {
          return engine::SharedShare(pixels, p) > engine::kSameObjectShare;
        });
        if (same) continue;
        kept.push_back(std::move(rec));
        kept_pixels.push_back(std::move(pixels));
      }
    }
    for (ObjectRecord& rec : kept) {
      PoseResult row;
      row.scene_id = key.scene_id;
      row.im_id = key.image_id;
      row.obj_id = obj_id;
      row.score = rec.estimate.best_weight;
      row.T_cam_obj = rec.estimate.T_cam_obj;
      out.rows.push_back(row);
      out.objects.push_back(std::move(rec));
      if (on_object) on_object(out.objects.back());
    }
  }
  // BOP's time column: the whole image, the same on each of its rows.
  const double image_s = std::chrono::duration<double>(Clock::now() - image_start).count();
  for (PoseResult& row : out.rows) row.time_s = image_s;
  return out;
}

namespace {

// The detections by image and class; each names an image of the dataset and a class with a
// model, and no image holds more than limits::kMaxBoxesPerImage boxes.
StatusOr<ImageGroups> GroupByImage(const Dataset& dataset, const std::vector<Detection>& detections,
                                   const std::string& detections_source) {
  const std::vector<FrameKey> frames = dataset.Frames();
  const std::set<FrameKey> frame_set(frames.begin(), frames.end());
  const std::vector<int> ids = dataset.ObjectIds();
  const std::set<int> id_set(ids.begin(), ids.end());
  ImageGroups groups;
  std::map<FrameKey, int> boxes_of_image;
  for (size_t i = 0; i < detections.size(); ++i) {
    const Detection& d = detections[i];
    const std::string where = detections_source + ": detection " + std::to_string(i) + " (scene_id " +
                              std::to_string(d.scene_id) + ", image_id " + std::to_string(d.image_id) + ")";
    const FrameKey key{d.scene_id, d.image_id};
    if (!frame_set.count(key)) return NotFound(where + ": no such image in " + dataset.root());
    if (!id_set.count(d.obj_id))
      return InvalidArgument(where + ": unknown class (category_id " + std::to_string(d.obj_id) +
                             "); the dataset has no model for it");
    if (++boxes_of_image[key] > limits::kMaxBoxesPerImage)
      return InvalidArgument(where + ": more than " + std::to_string(limits::kMaxBoxesPerImage) +
                             " boxes in one image");
    groups[key][d.obj_id].push_back(d);
  }
  return groups;
}

}  // namespace

Status CheckBoxesOfImage(const FrameKey& key, const std::map<int, std::vector<Detection>>& by_class,
                         const Intrinsics& K, const std::string& detections_source) {
  for (const auto& [obj_id, dets] : by_class)
    for (const Detection& d : dets)
      if (Status st = CheckBox(d, K); !st.ok())
        return InvalidArgument(detections_source + ": obj_id " + std::to_string(obj_id) + " in scene_id " +
                               std::to_string(key.scene_id) + ", image_id " + std::to_string(key.image_id) + ": " +
                               st.message());
  return Status::Ok();
}

Status CheckDetectionsAgainstDataset(const Dataset& dataset, const std::vector<Detection>& detections,
                                     const std::string& detections_source) {
  return GroupDetections(dataset, detections, detections_source).status();
}

StatusOr<ImageGroups> GroupDetections(const Dataset& dataset, const std::vector<Detection>& detections,
                                      const std::string& detections_source) {
  MCPOSE_ASSIGN_OR_RETURN(ImageGroups groups, GroupByImage(dataset, detections, detections_source));
  for (const auto& [key, by_class] : groups) {
    MCPOSE_ASSIGN_OR_RETURN(const Intrinsics K, dataset.LoadIntrinsics(key));  // no depth decoded
    MCPOSE_RETURN_IF_ERROR(CheckBoxesOfImage(key, by_class, K, detections_source));
  }
  return groups;
}

namespace {

// The classes of `by_class` whose boxes hold some depth: one with none has nothing to fit and
// gets no row (one warning naming the depth image and the class).
std::map<int, std::vector<Detection>> ClassesWithDepth(const Dataset& dataset, const Frame& frame,
                                                       const std::map<int, std::vector<Detection>>& by_class) {
  std::map<int, std::vector<Detection>> kept;
  for (const auto& [obj_id, dets] : by_class) {
    if (BoxesHoldDepth(frame.depth, dets)) {
      kept.emplace(obj_id, dets);
      continue;
    }
    spdlog::warn("{}: no valid depth in the {} box(es) of class {} ({}); it gets no result", frame.depth_path,
                 dets.size(), obj_id, dataset.ObjectName(obj_id));
  }
  return kept;
}

}  // namespace

StatusOr<ImageEstimate> EstimateFrame(Estimator& estimator, const Dataset& dataset, const Frame& frame,
                                      const std::map<int, std::vector<Detection>>& boxes,
                                      const std::map<int, const Mesh*>& meshes,
                                      const std::function<void(const ObjectRecord&)>& on_object,
                                      const std::map<int, int>* instances_of_class) {
  std::optional<ColourImage> colour;
  if (ImageWantsColour(estimator.options(), boxes, meshes)) {
    MCPOSE_ASSIGN_OR_RETURN(colour, dataset.LoadColour(frame));
  }
  return EstimateImage(estimator, frame.key, frame.K, frame.depth, colour ? &*colour : nullptr, boxes, meshes,
                       [&](int obj_id) { return dataset.ObjectName(obj_id); }, on_object, instances_of_class);
}

StatusOr<RunReport> RunEstimation(const Dataset& dataset, const std::vector<Detection>& detections,
                                  const std::string& detections_source,
                                  const EstimatorOptions& options, const ProgressFn& progress,
                                  const ImageDoneFn& image_done, const SkipImageFn& skip,
                                  const InstanceCounts* instance_counts) {
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<Estimator> estimator, Estimator::Create(options));
  return RunEstimation(*estimator, dataset, detections, detections_source, progress, image_done, skip,
                       instance_counts);
}

StatusOr<RunReport> RunEstimation(Estimator& estimator, const Dataset& dataset,
                                  const std::vector<Detection>& detections, const std::string& detections_source,
                                  const ProgressFn& progress, const ImageDoneFn& image_done,
                                  const SkipImageFn& skip, const InstanceCounts* instance_counts) {
  MCPOSE_ASSIGN_OR_RETURN(const ImageGroups groups, GroupDetections(dataset, detections, detections_source));

  // ---- Load the meshes before estimating anything -----------------------------------------
  std::map<int, Mesh> meshes;
  for (const auto& [key, by_class] : groups) {
    for (const auto& [obj_id, dets] : by_class) {
      if (!meshes.count(obj_id)) {
        MCPOSE_ASSIGN_OR_RETURN(Mesh mesh, dataset.LoadMesh(obj_id));
        meshes.emplace(obj_id, std::move(mesh));
      }
    }
  }
  int total = 0;
  for (const auto& [key, by_class] : groups) total += static_cast<int>(by_class.size());
  std::vector<const Mesh*> mesh_list;
  for (const auto& [obj_id, mesh] : meshes) mesh_list.push_back(&mesh);
  estimator.PrepareMeshes(mesh_list);  // the LOD chains and colour grids, a mesh per raster core

  // ---- Estimate each (image, class) ------------------------------------------------------
  const std::map<int, const Mesh*> mesh_of = [&] {
    std::map<int, const Mesh*> m;
    for (const auto& [obj_id, mesh] : meshes) m.emplace(obj_id, &mesh);
    return m;
  }();
  RunReport report;
  int done = 0;
  for (const auto& [key, by_class] : groups) {
    if (skip && skip(key)) {
      done += static_cast<int>(by_class.size());
      continue;
    }
    MCPOSE_ASSIGN_OR_RETURN(Frame frame, dataset.LoadFrame(key));  // each frame decoded here only
    const std::map<int, std::vector<Detection>> with_depth = ClassesWithDepth(dataset, frame, by_class);
    total -= static_cast<int>(by_class.size() - with_depth.size());
    if (with_depth.empty()) continue;
    const auto on_object = [&](const ObjectRecord& r) {
      if (r.instance == 0) ++done;  // progress counts classes; a class's further instances follow it
      if (progress) progress(done, total, r);
    };
    std::map<int, int> instances_of_class;
    if (instance_counts)
      for (const auto& [obj_id, dets] : with_depth)
        if (const auto it = instance_counts->find({key, obj_id}); it != instance_counts->end())
          instances_of_class.emplace(obj_id, it->second);
    MCPOSE_ASSIGN_OR_RETURN(ImageEstimate image, EstimateFrame(estimator, dataset, frame, with_depth, mesh_of, on_object,
                                                               &instances_of_class));
    if (image_done) MCPOSE_RETURN_IF_ERROR(image_done(key, image.rows));
    report.results.insert(report.results.end(), image.rows.begin(), image.rows.end());
    for (ObjectRecord& r : image.objects) report.objects.push_back(std::move(r));
  }
  return report;
}

}  // namespace mcpose

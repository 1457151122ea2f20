// The whole estimation job: detections of many images -> one pose per (image, class).
#pragma once

#include <functional>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "mcpose/dataset.h"
#include "mcpose/detection.h"
#include "mcpose/estimator.h"
#include "mcpose/options.h"
#include "mcpose/results.h"
#include "mcpose/status.h"
#include "mcpose/tracker.h"

namespace mcpose {

struct ObjectRecord {
  FrameKey key;
  int obj_id = 0;
  int instance = 0;      // 0: the filter over all the class's boxes; k > 0: the k-th further object
  std::string name;
  int num_boxes = 0;     // the boxes its filter sampled
  Detection chosen_box;  // the box of the best sample
  ObjectEstimate estimate;
  double time_s = 0;     // wall time of this object
};

struct RunReport {
  std::vector<PoseResult> results;    // BOP rows, sorted by (scene, image, obj), then instance
  std::vector<ObjectRecord> objects;  // the same order
};

// Called after each object with (objects done, objects in all, the record).
using ProgressFn = std::function<void(int, int, const ObjectRecord&)>;
// Called after each image with its rows (sorted by obj_id); an error stops the run with it.
using ImageDoneFn = std::function<Status(const FrameKey&, const std::vector<PoseResult>&)>;
// True for an image not to estimate (one an earlier run finished).
using SkipImageFn = std::function<bool(const FrameKey&)>;

// One image's estimates: a record and a BOP row per instance, sorted by obj_id, then instance;
// each row's time is the whole image's.
struct ImageEstimate {
  std::vector<ObjectRecord> objects;
  std::vector<PoseResult> rows;
};

// Estimates each class of one image from its boxes (`boxes` by obj_id, every class with a mesh
// in `meshes`): its first instance from all its boxes, then up to options().max_instances in
// all, as engine/instances.h says; `instances_of_class` (obj_id -> count, may be null) overrides
// that limit for the classes it names (BOP's inst_count). `colour` may be null; it is used only
// when the options allow colour and some class's mesh has it. `name_of` names a class for its
// record (may be null); `on_object` is called after each instance (may be null).
StatusOr<ImageEstimate> EstimateImage(Estimator& estimator, const FrameKey& key, const Intrinsics& K,
                                      const DepthImage& depth, const ColourImage* colour,
                                      const std::map<int, std::vector<Detection>>& boxes,
                                      const std::map<int, const Mesh*>& meshes,
                                      const std::function<std::string(int)>& name_of,
                                      const std::function<void(const ObjectRecord&)>& on_object,
                                      const std::map<int, int>* instances_of_class = nullptr);

// EstimateImage on a frame of `dataset`, its colour image read only when it is used: one
// image's step of RunEstimation. Classes are named by the dataset.
StatusOr<ImageEstimate> EstimateFrame(Estimator& estimator, const Dataset& dataset, const Frame& frame,
                                      const std::map<int, std::vector<Detection>>& boxes,
                                      const std::map<int, const Mesh*>& meshes,
                                      const std::function<void(const ObjectRecord&)>& on_object,
                                      const std::map<int, int>* instances_of_class = nullptr);

// Whether EstimateImage would use a colour image for these classes: read it only then.
bool ImageWantsColour(const EstimatorOptions& options, const std::map<int, std::vector<Detection>>& boxes,
                      const std::map<int, const Mesh*>& meshes);

using ImageGroups = std::map<FrameKey, std::map<int, std::vector<Detection>>>;

// The detections by image and class, each checked as CheckDetectionsAgainstDataset does (the
// frames' intrinsics read, no depth image decoded). RunEstimation leaves out, with one warning
// naming the depth image and the class, a class whose boxes hold no valid depth.
StatusOr<ImageGroups> GroupDetections(const Dataset& dataset, const std::vector<Detection>& detections,
                                      const std::string& detections_source);

// The one check of detections against a dataset, for every command that reads both: each
// detection's image exists in the dataset, its class has a model, no image holds more than
// limits::kMaxBoxesPerImage boxes, and each box passes CheckBox in its image (each named
// image's intrinsics and size are read: Dataset::LoadIntrinsics). Errors name
// `detections_source` and the detection.
Status CheckDetectionsAgainstDataset(const Dataset& dataset, const std::vector<Detection>& detections,
                                     const std::string& detections_source);

// The boxes of one image, by class, against its intrinsics (the per-image part of the check
// above); errors name `detections_source`, the image and the class.
Status CheckBoxesOfImage(const FrameKey& key, const std::map<int, std::vector<Detection>>& by_class,
                         const Intrinsics& K, const std::string& detections_source);

// Instances of a class an image holds, by (image, obj_id): BOP's inst_count.
using InstanceCounts = std::map<std::pair<FrameKey, int>, int>;

// Checks every detection first (GroupDetections), loads the meshes, then estimates each (image, class) group, images in (scene_id, image_id) order,
// leaving out those `skip` names. Nothing is written here; `image_done` may write each image.
StatusOr<RunReport> RunEstimation(const Dataset& dataset, const std::vector<Detection>& detections,
                                  const std::string& detections_source,
                                  const EstimatorOptions& options, const ProgressFn& progress,
                                  const ImageDoneFn& image_done = nullptr, const SkipImageFn& skip = nullptr,
                                  const InstanceCounts* instance_counts = nullptr);
// The same with an estimator made earlier (its options are the run's).
StatusOr<RunReport> RunEstimation(Estimator& estimator, const Dataset& dataset,
                                  const std::vector<Detection>& detections, const std::string& detections_source,
                                  const ProgressFn& progress, const ImageDoneFn& image_done = nullptr,
                                  const SkipImageFn& skip = nullptr, const InstanceCounts* instance_counts = nullptr);

// ---- Tracking a video (mcpose track) ---------------------------------------------------------

// One object in one frame of a tracking run.
struct TrackRecord {
  FrameKey key;
  std::string name;  // the class's name in the dataset
  TrackStep step;
};

struct TrackReport {
  std::vector<PoseResult> results;  // one BOP row per (frame, object), sorted; a row's time is its frame's
  std::vector<TrackRecord> steps;   // in the order they were tracked: frame by frame, classes in order
};

// Which frames of which video to track, and from which boxes.
struct TrackRun {
  int video = -1;                                      // scene_id
  int first_frame = 0, last_frame = std::numeric_limits<int>::max();  // inclusive
  // The boxes that start (and restart lost) tracks; null: tight boxes of the ground-truth
  // visible masks. Checked against the dataset (CheckDetectionsAgainstDataset).
  const std::vector<Detection>* detections = nullptr;
  std::string detections_source = "detections";  // names them in errors
};

// Tracks every object of the run's frames with a Tracker of `options`, frame by frame; each
// record goes to `progress` (may be null) as it is made. Nothing is written here.
StatusOr<TrackReport> RunTracking(const Dataset& dataset, const TrackRun& run, const TrackerOptions& options,
                                  const std::function<void(const TrackRecord&)>& progress = nullptr);

// The stream id of one (image, class) group: results depend on (seed, this) only.
uint64_t GroupStreamId(int scene_id, int image_id, int obj_id);

}  // namespace mcpose

// The whole estimation job: detections of many images -> one pose per (image, class).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "mcpose/dataset.h"
#include "mcpose/detection.h"
#include "mcpose/estimator.h"
#include "mcpose/options.h"
#include "mcpose/results.h"
#include "mcpose/status.h"

namespace mcpose {

struct ObjectRecord {
  FrameKey key;
  int obj_id = 0;
  std::string name;
  int num_boxes = 0;
  Detection chosen_box;  // the box of the best sample
  ObjectEstimate estimate;
  double time_s = 0;     // wall time of this object
};

struct RunReport {
  std::vector<PoseResult> results;    // BOP rows, sorted by (scene, image, obj)
  std::vector<ObjectRecord> objects;  // the same order
};

// Called after each object with (objects done, objects in all, the record).
using ProgressFn = std::function<void(int, int, const ObjectRecord&)>;

// Checks every detection first (its image exists in the dataset, its class has a model, its
// box lies in the image with positive size; errors name `detections_source`), loads the
// meshes, then estimates each (image, class) group. A class whose boxes hold no valid depth is
// left out with one warning naming the depth image and the class. Nothing is written here.
StatusOr<RunReport> RunEstimation(const Dataset& dataset, const std::vector<Detection>& detections,
                                  const std::string& detections_source,
                                  const EstimatorOptions& options, const ProgressFn& progress);

// The stream id of one (image, class) group: results depend on (seed, this) only.
uint64_t GroupStreamId(int scene_id, int image_id, int obj_id);

}  // namespace mcpose

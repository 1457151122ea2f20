// The per-object detail `mcpose estimate --out-json` writes, as the report reads it: the pose,
// the chosen box, and each iteration's mean and best weight.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "mcpose/dataset.h"
#include "mcpose/detection.h"
#include "mcpose/se3.h"
#include "mcpose/status.h"

namespace mcpose::report {

struct IterationWeights {
  double mean_weight = 0, best_weight = 0;
};

struct ObjectDetail {
  FrameKey key;
  int obj_id = 0;
  SE3 T_cam_obj;        // metres
  Detection chosen_box;  // the box of the best sample, as the detections file gave it
  int boxes = 0;         // boxes of the class in the image
  std::vector<IterationWeights> per_iteration;
  double best_weight = NAN, final_mean_weight = NAN, time_s = NAN;
  // After the filter (absent from older files: false / NaN): the twin resolution and the
  // alignment to the observed depth.
  bool twins_ran = false;
  int twin_candidates = 0;
  bool refine_accepted = false;
  double refine_rms_before_mm = NAN, refine_rms_after_mm = NAN;
};

struct EstimateDetail {
  double tau = NAN;  // the stopping threshold of the run, if the file records its options
  std::vector<ObjectDetail> objects;
};

// Reads the file. Errors name the file and, for a bad entry, "objects[i]" and the field.
StatusOr<EstimateDetail> ReadEstimateDetail(const std::string& path);

}  // namespace mcpose::report

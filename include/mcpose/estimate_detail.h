// The detail JSON of a run, written and read in one place: what `mcpose estimate --out-json`
// writes (every object's pose, chosen box, per-iteration weights and times, twins, refinement and
// engine counters, with the run's options) and what `mcpose report` reads back of it; and what
// `mcpose track --out-json` writes.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mcpose/dataset.h"
#include "mcpose/detection.h"
#include "mcpose/options.h"
#include "mcpose/run.h"
#include "mcpose/se3.h"
#include "mcpose/status.h"
#include "mcpose/tracker.h"

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

// The detail of an estimation run: {"dataset", "models", "detections", "options" (with the SIMD
// target the kernels dispatched to), "objects": [one per record of `report`]}.
nlohmann::json EstimateDetailJson(const RunReport& report, const EstimatorOptions& options, const std::string& dataset,
                                  const std::string& models, const std::string& detections);
// The detail of a tracking run: {"dataset", "video", "options", "steps": [one per record]}.
nlohmann::json TrackDetailJson(const TrackReport& report, const TrackerOptions& options, const std::string& dataset,
                               int video);

// Reads the file `mcpose estimate --out-json` wrote. Errors name the file and, for a bad entry, "objects[i]" and the field.
StatusOr<EstimateDetail> ReadEstimateDetail(const std::string& path);

}  // namespace mcpose::report

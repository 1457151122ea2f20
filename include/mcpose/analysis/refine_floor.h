// Refinement floor: how close the depth alignment of the refinement stage (refine/align.h)
// lands to the ground truth when it starts at the ground truth, or a given distance from it.
//
// The alignment fits the model to the observed depth; where the dataset's ground-truth pose and
// its depth disagree, the aligned pose leaves the truth by that disagreement (on YCB-Video a few
// pixels across the viewing ray, the same through a video for one object and different for
// the next: the annotation, not the camera). Its ADD-S to the truth is the precision no refinement of an
// estimator in the right basin can beat on that frame as the truth measures it, and the ADD-S
// AUC of the aligned poses is the AUC such an estimator would reach if every answer were in the
// right basin.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mcpose/camera.h"
#include "mcpose/dataset.h"
#include "mcpose/image.h"
#include "mcpose/mesh.h"
#include "mcpose/options.h"
#include "mcpose/se3.h"
#include "mcpose/status.h"

namespace mcpose::analysis {

struct RefineFloorOptions {
  RefineOptions refine;          // the alignment's max_iterations, tukey_m and max_distance_m
  double start_mm = 0;           // the start: the truth moved this far in a random direction
  double start_deg = 0;          // and turned this far about a random axis
  double box_margin = 0.1;       // the tight visible-mask box grown by this share of its size per side
  uint64_t seed = 0;             // of the random starts
  double auc_max_m = 0.1;        // the AUC's range (YCB-Video: 10 cm)
  bool IsValid(std::string* error) const;
};

struct InstanceFloor {
  FrameKey key;
  int obj_id = 0;
  double adds_start_m = 0;    // ADD-S of the start to the truth
  double adds_aligned_m = 0;  // ADD-S of the aligned pose to the truth
  double along_ray_mm = 0;    // the aligned pose's origin minus the truth's, along the viewing ray
  double across_ray_mm = 0;   // and across it (in the image plane)
  int iterations = 0;
};

struct RefineFloorReport {
  std::vector<InstanceFloor> instances;
  struct Row {
    int obj_id = 0;  // 0: all instances
    std::string name;
    int instances = 0;
    double mean_start_mm = 0, mean_aligned_mm = 0, median_aligned_mm = 0, mean_across_ray_mm = 0;
    double auc = 0;  // ADD-S AUC of the aligned poses, 0-1
  };
  std::vector<Row> per_object;  // sorted by obj_id
  Row overall;
};

// Every ground-truth instance with a visible pixel of the real frames (not the synthetic ones,
// rendered from their truth), in its visible-mask box grown by options.box_margin. `progress`
// (may be null) is called after each frame.
StatusOr<RefineFloorReport> AnalyzeRefineFloor(const Dataset& dataset, const RefineFloorOptions& options,
                                               void (*progress)(int done, int total) = nullptr);

}  // namespace mcpose::analysis

// Depth ambiguity: how many poses of an object a depth-only score cannot tell apart from the
// ground truth, and what that caps the accuracy of any depth-only estimator at.
//
// For each ground-truth instance, candidate poses are the ground truth turned about the model's
// bounding-box centre: F then a rotation of k * step about one model axis, for the flips
// F in {I, 180 deg about x, y, z}. A candidate is *depth-equivalent* when its rendered depth
// agrees with the ground truth's render (both rendered, |dz| < agree_eps) on at least
// min_agreement of the pixels where either renders, leaving out the pixels where the observed
// surface lies in front of both (occluded by something else). An estimator that sees only
// depth, finds the right equivalence class and picks in it at random scores ADD(-S) < threshold
// with probability `ceiling` = (equivalent candidates within the threshold) / (equivalent
// candidates); the identity is always one of them.
//
// The candidates are not every rotation: a depth-equivalent pose that is no turn about a model
// axis (after a flip) is missed, so the ceiling is an upper bound. On the YCB-Video frames the
// banana has such a twin (found by the estimator: ADD-S 3 mm, ADD 10 cm) that this set lacks.
#pragma once

#include <string>
#include <vector>

#include "mcpose/camera.h"
#include "mcpose/dataset.h"
#include "mcpose/image.h"
#include "mcpose/mesh.h"
#include "mcpose/se3.h"
#include "mcpose/status.h"

#include <Eigen/Core>

namespace mcpose::analysis {

struct AmbiguityOptions {
  double step_deg = 15.0;       // rotation step about each model axis
  double agree_eps_m = 0.005;   // two renders agree at a pixel within this depth difference
  double min_agreement = 0.95;  // share of compared pixels that must agree
  double occlusion_eps_m = 0.01;  // observed surface this far in front of both: not compared
  double threshold_m = 0.04;    // ADD(-S) threshold of the ceiling
  bool IsValid(std::string* error) const;
};

struct InstanceAmbiguity {
  FrameKey key;
  int obj_id = 0;
  int candidates = 0;          // distinct candidate rotations, the identity included
  int equivalent = 0;          // depth-equivalent candidates (>= 1: the identity)
  int equivalent_correct = 0;  // of those, ADD(-S) to the ground truth < threshold
  double ceiling = 0;          // equivalent_correct / equivalent
};


struct AmbiguityReport {
  std::vector<InstanceAmbiguity> instances;
  struct Row {
    int obj_id = 0;  // 0: all instances
    std::string name;
    int instances = 0;
    double mean_equivalent = 0;  // mean depth-equivalent candidates per instance
    double ceiling = 0;          // mean ceiling: expected share of ADD(-S) < threshold
  };
  std::vector<Row> per_object;  // sorted by obj_id
  Row overall;
};

// Every ground-truth instance with a visible pixel, in its tight visible-mask box, scored with
// the YCB-Video ADD(-S) symmetric set. `progress` (may be null) is called after each frame.
StatusOr<AmbiguityReport> AnalyzeDataset(const Dataset& dataset, const AmbiguityOptions& options,
                                         void (*progress)(int done, int total) = nullptr);

}  // namespace mcpose::analysis

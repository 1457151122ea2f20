// Pose accuracy in the YCB-Video protocol (PoseCNN): ADD, ADD-S and ADD(-S), shares under
// 2 cm and 4 cm, and the area under the accuracy-threshold curve up to 10 cm.
#pragma once

#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "mcpose/dataset.h"
#include "mcpose/detection.h"
#include "mcpose/results.h"
#include "mcpose/se3.h"
#include "mcpose/status.h"

namespace mcpose {

// Mean distance between corresponding model points under the two poses (metres).
double Add(const std::vector<Eigen::Vector3f>& points_m, const SE3& T_est, const SE3& T_gt);
// Mean distance from each ground-truth-posed point to the closest estimate-posed point.
double AddS(const std::vector<Eigen::Vector3f>& points_m, const SE3& T_est, const SE3& T_gt);
// Area under the accuracy curve acc(x) = share of errors < x, for x in [0, max_m], divided by
// max_m (so 1.0 is perfect). Missing results enter as +infinity.
double AccuracyAuc(const std::vector<double>& errors_m, double max_m);

// The YCB-Video ADD-S set: 024_bowl, 036_wood_block, 051_large_clamp, 052_extra_large_clamp,
// 061_foam_brick (obj_ids 13, 16, 19, 20, 21).
std::set<int> YcbvSymmetricObjectIds();

struct EvalOptions {
  double auc_max_m = 0.10;
  std::set<int> symmetric_obj_ids = YcbvSymmetricObjectIds();  // scored with ADD-S in ADD(-S)
};

struct InstanceEval {
  FrameKey key;
  int obj_id = 0;
  int gt_index = 0;
  int visible_pixels = 0;
  bool has_result = false;
  int result_index = -1;  // the row of the results scored against it; -1 without one
  double add_m = 0, adds_m = 0, add_or_adds_m = 0;  // +infinity when has_result is false
  // The estimate relative to the truth, R_gt^T R_est as an angle (degrees) about an axis in the
  // model frame, and |t_est - t_gt| (mm); NaN when has_result is false.
  double rotation_error_deg = NAN, translation_error_mm = NAN;
  Eigen::Vector3d rotation_error_axis = Eigen::Vector3d::Constant(NAN);
};

struct AccuracySummary {
  int obj_id = 0;  // 0 for the overall row
  std::string name;
  int instances = 0;
  int with_result = 0;
  double add_lt_2cm = 0, add_lt_4cm = 0, add_auc = 0;           // shares in [0, 1]
  double adds_lt_2cm = 0, adds_lt_4cm = 0, adds_auc = 0;
  double add_s_lt_2cm = 0, add_s_lt_4cm = 0, add_s_auc = 0;     // ADD(-S)
};

struct EvalReport {
  std::vector<InstanceEval> instances;
  std::vector<AccuracySummary> per_object;  // sorted by obj_id
  AccuracySummary overall;
  // Result rows whose (scene_id, im_id, obj_id) matches no target (no visible ground-truth
  // instance of that object in an evaluated frame): not scored.
  int unmatched_rows = 0;
};

// Targets: every ground-truth instance with at least one visible pixel, in every frame of the
// dataset, or, if `detections` is non-null, in the frames that have a detection. A target
// without a result row (same scene_id, im_id, obj_id) counts as a failure (error = infinity).
// If several rows match, the one with the highest score is used.
StatusOr<EvalReport> Evaluate(const Dataset& dataset, const std::vector<PoseResult>& results,
                              const std::vector<Detection>* detections, const EvalOptions& options);

// Tight box of the nonzero pixels of a mask in the BOP box convention: pixels x .. x + w - 1,
// y .. y + h - 1. Returns the number of nonzero pixels; for an empty mask (0) `box` is untouched.
int MaskBox(const MaskImage& mask, Detection* box);

// Options of detector-like boxes made from ground-truth visible masks.
struct GtDetectionOptions {
  double jitter = 0.1;       // each side moved by up to jitter * box size (uniform)
  double distractors = 0.3;  // probability of one extra same-class box elsewhere
  uint64_t seed = 0;
  int min_visible_pixels = 1;
};

// Boxes from the visible masks of every ground-truth instance: score U(0.5, 1); with
// probability `distractors` an extra box of the same class and size at a random place in the
// image with score U(0.2, 0.7). Boxes are clipped to the image. Deterministic for a seed.
StatusOr<std::vector<Detection>> DetectionsFromGroundTruth(const Dataset& dataset,
                                                           const GtDetectionOptions& options);

}  // namespace mcpose

// The BOP19 pose-error metrics and their average recall, as the BOP benchmark defines them
// (bop_toolkit: pose_error.py, misc.get_symmetry_transformations, pose_matching.py, score.py,
// scripts/eval_bop19_pose.py): VSD, MSSD and MSPD, each a recall over a range of thresholds,
// and AR, the mean of the three.
//
// Units: metres and pixels (BOP's files are in millimetres; the readers convert).
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

#include "mcpose/camera.h"
#include "mcpose/dataset.h"
#include "mcpose/image.h"
#include "mcpose/mesh.h"
#include "mcpose/results.h"
#include "mcpose/se3.h"
#include "mcpose/status.h"

namespace mcpose {

// A continuous symmetry: any turn about `axis` through the point `offset_m` (model frame).
struct ContinuousSymmetry {
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d offset_m = Eigen::Vector3d::Zero();
};

// What models_info.json says of one object.
struct ModelInfo {
  double diameter_m = 0;
  std::vector<SE3> discrete;  // x -> R x + t that leave the object's look unchanged (identity not listed)
  std::vector<ContinuousSymmetry> continuous;
};

// Reads a BOP models_info.json (millimetres): every object's diameter and symmetries. Errors
// name the file and the object: a diameter that is not a positive finite size under 200 m, a
// discrete symmetry that is not 16 finite numbers of a rigid transform, an axis of zero length.
StatusOr<std::map<int, ModelInfo>> ReadModelsInfo(const std::string& path);

// The symmetry transformations of an object, as bop_toolkit discretises them: the identity and
// each discrete symmetry; each continuous symmetry as n = ceil(pi / max_sym_disc_step) turns of
// 2 pi / n about its axis (so that no vertex moves more than that share of the diameter
// between two), and every continuous turn composed with every discrete one.
std::vector<SE3> SymmetryTransformations(const ModelInfo& info, double max_sym_disc_step = 0.01);

// Maximum Symmetry-aware Surface Distance (metres): min over the symmetries S of the largest
// distance between a point posed by T_est and the same point posed by T_gt S.
double Mssd(const std::vector<Eigen::Vector3f>& points_m, const SE3& T_est, const SE3& T_gt,
            const std::vector<SE3>& symmetries);

// Maximum Symmetry-aware Projection Distance (pixels): as MSSD, with the points projected by K.
double Mspd(const std::vector<Eigen::Vector3f>& points_m, const SE3& T_est, const SE3& T_gt,
            const std::vector<SE3>& symmetries, const Intrinsics& K);

// Visible Surface Discrepancy, one error per tau (taus as shares of the diameter), with the step
// cost and BOP19's visibility: the mesh rendered at either pose over the whole image, depth
// turned into distance from the camera centre; a rendered pixel is visible where it lies at most
// `delta_m` behind the test image's distance or the test image has none (0); the estimate is
// also visible where the truth is. Each error is the share of the union of the two visible masks
// whose pixel is not in both or differs by tau * diameter or more; 1 for an empty union, and
// for poses whose bounding spheres do not overlap in the image (not rendered).
std::vector<double> Vsd(const DepthImage& test_depth, const Intrinsics& K, const Mesh& mesh, const SE3& T_est,
                        const SE3& T_gt, double diameter_m, double delta_m, const std::vector<double>& taus);

// One target of the benchmark: `inst_count` instances of obj_id in an image.
struct Bop19Target {
  FrameKey key;
  int obj_id = 0;
  int inst_count = 0;
};

// Reads BOP's test_targets_bop19.json: a list of {"scene_id", "im_id", "obj_id", "inst_count"}.
StatusOr<std::vector<Bop19Target>> ReadBop19Targets(const std::string& path);

struct Bop19Options {
  double vsd_delta_m = 0.015;                                                        // BOP19: 15 mm
  std::vector<double> vsd_taus = {0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.45, 0.5};  // x diameter
  std::vector<double> vsd_thresholds = {0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.45, 0.5};
  std::vector<double> mssd_thresholds = {0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.45, 0.5};  // x diameter
  std::vector<double> mspd_thresholds_px = {5, 10, 15, 20, 25, 30, 35, 40, 45, 50};  // x image width / 640
  double max_sym_disc_step = 0.01;
  // Without a targets file: the instances of at least this visible share of their silhouette
  // are the targets (BOP19's rule for test_targets_bop19.json).
  double min_visible_fraction = 0.1;
};

// The errors of one estimate against one ground-truth instance of its object.
struct Bop19Errors {
  std::vector<double> vsd;  // one per tau
  double mssd_m = 0, mspd_px = 0;
};

// One ground-truth instance of a target: valid if it is among the `inst_count` most visible of
// its object in the image. `errors[e]` is estimate e's errors against it (estimates of the same
// (image, object) in descending score order).
struct Bop19Instance {
  FrameKey key;
  int obj_id = 0;
  int gt_index = 0;
  double diameter_m = 0;  // the object's
  int image_width = 0;    // MSPD's thresholds scale with it (x width / 640)
  double visible_fraction = 0;
  bool valid = false;
  std::vector<Bop19Errors> errors;
};

struct Bop19Summary {
  int obj_id = 0;  // 0: all objects
  std::string name;
  int targets = 0;  // valid instances
  double ar_vsd = 0, ar_mssd = 0, ar_mspd = 0, ar = 0;
};

struct Bop19Report {
  std::vector<Bop19Instance> instances;
  std::vector<Bop19Summary> per_object;  // sorted by obj_id
  Bop19Summary overall;                  // recalls pooled over every target (as BOP's)
};

// The recalls of a set of (image, object) groups of instances: per threshold, each group's
// estimates in order take the not yet matched valid instance of least error below the threshold
// (greedy, as bop_toolkit's match_poses); recall = matched valid instances / valid instances,
// averaged over the thresholds (VSD: over every tau and threshold). No valid instance: 0.
Bop19Summary Bop19Recalls(const std::vector<const Bop19Instance*>& instances, const Bop19Options& options);

// The BOP19 evaluation of `results` on the frames of `dataset` (or those of them `frames` names,
// if not null): the targets from `targets` (may be null: every instance of at least
// min_visible_fraction visible, counted per image and object); per target the inst_count best-scored rows of its object (ties: the first row);
// errors against every instance of the object; AR per object and pooled. The visible fraction of
// an instance is its visible mask's pixels over its silhouette rendered at the true pose.
StatusOr<Bop19Report> EvaluateBop19(const Dataset& dataset, const std::vector<PoseResult>& results,
                                    const std::map<int, ModelInfo>& models_info,
                                    const std::vector<Bop19Target>* targets, const Bop19Options& options,
                                    const std::set<FrameKey>* frames = nullptr);

}  // namespace mcpose

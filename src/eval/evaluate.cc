// Evaluate: ground-truth targets, result matching and the per-object / overall summaries of
// the YCB-Video protocol.

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "mcpose/eval.h"

namespace mcpose {
namespace {

using ResultKey = std::tuple<int, int, int>;  // (scene_id, im_id, obj_id)

int CountNonZero(const MaskImage& mask) {
  return static_cast<int>(
      std::count_if(mask.values.begin(), mask.values.end(), [](uint8_t v) { return v != 0; }));
}

double ShareBelow(const std::vector<double>& errors_m, double threshold_m) {
  if (errors_m.empty()) return 0.0;
  const auto below = std::count_if(errors_m.begin(), errors_m.end(),
                                   [threshold_m](double e) { return e < threshold_m; });
  return static_cast<double>(below) / static_cast<double>(errors_m.size());
}

AccuracySummary Summarize(int obj_id, std::string name,
                          const std::vector<const InstanceEval*>& instances, double auc_max_m) {
  AccuracySummary s;
  s.obj_id = obj_id;
  s.name = std::move(name);
  s.instances = static_cast<int>(instances.size());
  std::vector<double> add, adds, add_s;
  add.reserve(instances.size());
  adds.reserve(instances.size());
  add_s.reserve(instances.size());
  for (const InstanceEval* e : instances) {
    if (e->has_result) ++s.with_result;
    add.push_back(e->add_m);
    adds.push_back(e->adds_m);
    add_s.push_back(e->add_or_adds_m);
  }
  s.add_lt_2cm = ShareBelow(add, 0.02);
  s.add_lt_4cm = ShareBelow(add, 0.04);
  s.add_auc = AccuracyAuc(add, auc_max_m);
  s.adds_lt_2cm = ShareBelow(adds, 0.02);
  s.adds_lt_4cm = ShareBelow(adds, 0.04);
  s.adds_auc = AccuracyAuc(adds, auc_max_m);
  s.add_s_lt_2cm = ShareBelow(add_s, 0.02);
  s.add_s_lt_4cm = ShareBelow(add_s, 0.04);
  s.add_s_auc = AccuracyAuc(add_s, auc_max_m);
  return s;
}

double FiniteOrInfinity(double e) { return std::isfinite(e) ? e : INFINITY; }

}  // namespace

// Notes on the protocol as implemented:
//  * Results are matched per (scene_id, im_id, obj_id), as in the YCB-Video protocol, where an
//    object appears at most once per image; should a frame hold two instances of one object,
//    both are scored against the same best row.
//  * Among rows with the same key the highest score wins; on a tie, the first row.
//  * Frames named by `detections` but absent from the dataset are ignored.
//  * Rows that match no target are counted (unmatched_rows), not scored.
//  * A non-finite error (a result with a NaN pose) is stored as +infinity: a failure.
StatusOr<EvalReport> Evaluate(const Dataset& dataset, const std::vector<PoseResult>& results,
                              const std::vector<Detection>* detections,
                              const EvalOptions& options) {
  if (!(options.auc_max_m > 0.0) || !std::isfinite(options.auc_max_m)) {
    return InvalidArgument("EvalOptions.auc_max_m must be finite and > 0, got " +
                           std::to_string(options.auc_max_m));
  }

  // Best result row per (scene_id, im_id, obj_id).
  std::map<ResultKey, const PoseResult*> best;
  for (const PoseResult& r : results) {
    auto [it, inserted] = best.try_emplace(ResultKey{r.scene_id, r.im_id, r.obj_id}, &r);
    if (!inserted && r.score > it->second->score) it->second = &r;
  }

  // Frames to evaluate: all, or those with a detection.
  std::vector<FrameKey> frames = dataset.Frames();
  std::sort(frames.begin(), frames.end());
  if (detections != nullptr) {
    std::set<FrameKey> detected;
    for (const Detection& d : *detections) detected.insert(FrameKey{d.scene_id, d.image_id});
    std::erase_if(frames, [&detected](const FrameKey& k) { return !detected.contains(k); });
  }

  EvalReport report;
  std::set<ResultKey> matched;  // keys of the rows that met a target
  std::map<int, std::vector<Eigen::Vector3f>> eval_points;  // per obj_id, loaded once
  for (const FrameKey& key : frames) {
    MCPOSE_ASSIGN_OR_RETURN(const Frame frame, dataset.LoadFrame(key));
    for (const GtInstance& gt : frame.gt) {
      // Targets: instances with at least one visible pixel.
      MCPOSE_ASSIGN_OR_RETURN(const MaskImage mask, dataset.LoadVisibleMask(key, gt));
      const int visible = CountNonZero(mask);
      if (visible == 0) continue;

      InstanceEval e;
      e.key = key;
      e.obj_id = gt.obj_id;
      e.gt_index = gt.gt_index;
      e.visible_pixels = visible;

      const auto row = best.find(ResultKey{key.scene_id, key.image_id, gt.obj_id});
      if (row != best.end()) matched.insert(row->first);
      if (row == best.end()) {
        e.add_m = e.adds_m = e.add_or_adds_m = INFINITY;
      } else {
        auto points = eval_points.find(gt.obj_id);
        if (points == eval_points.end()) {
          MCPOSE_ASSIGN_OR_RETURN(std::vector<Eigen::Vector3f> loaded,
                                  dataset.LoadEvalPoints(gt.obj_id));
          if (loaded.empty()) {
            return InvalidArgument("no evaluation points for obj_id " +
                                   std::to_string(gt.obj_id) + " (" +
                                   dataset.ObjectName(gt.obj_id) + ") in " + dataset.root());
          }
          points = eval_points.emplace(gt.obj_id, std::move(loaded)).first;
        }
        const SE3& T_est = row->second->T_cam_obj;
        e.has_result = true;
        e.add_m = FiniteOrInfinity(Add(points->second, T_est, gt.T_cam_obj));
        e.adds_m = FiniteOrInfinity(AddS(points->second, T_est, gt.T_cam_obj));
        e.add_or_adds_m = options.symmetric_obj_ids.contains(gt.obj_id) ? e.adds_m : e.add_m;
        const Eigen::Vector3d w = LogSO3(gt.T_cam_obj.R.transpose() * T_est.R);
        e.rotation_error_deg = w.norm() * 180 / M_PI;
        e.rotation_error_axis = w.norm() > 0 ? Eigen::Vector3d(w.normalized()) : Eigen::Vector3d::Zero();
        e.translation_error_mm = 1000 * (T_est.t - gt.T_cam_obj.t).norm();
      }
      report.instances.push_back(e);
    }
  }

  for (const PoseResult& r : results)
    report.unmatched_rows += !matched.contains(ResultKey{r.scene_id, r.im_id, r.obj_id});

  // Summaries: one row per object with targets, then all targets together.
  std::map<int, std::vector<const InstanceEval*>> by_object;
  std::vector<const InstanceEval*> all;
  all.reserve(report.instances.size());
  for (const InstanceEval& e : report.instances) {
    by_object[e.obj_id].push_back(&e);
    all.push_back(&e);
  }
  for (const auto& [obj_id, instances] : by_object) {
    report.per_object.push_back(
        Summarize(obj_id, dataset.ObjectName(obj_id), instances, options.auc_max_m));
  }
  report.overall = Summarize(0, "ALL", all, options.auc_max_m);
  return report;
}

}  // namespace mcpose

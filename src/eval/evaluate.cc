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
//  * Results are matched per (scene_id, im_id, obj_id), as in the YCB-Video protocol. Where a
//    frame holds one instance of an object, the row of the highest score is its result (on a
//    tie, the first row). Where it holds several, the rows in order of score each take the
//    instance still without a row that is nearest to it by ADD-S, as BOP matches estimates to
//    ground truth; an instance left over has no result.
//  * Frames named by `detections` but absent from the dataset are ignored.
//  * Rows whose (image, class) has no target are counted (unmatched_rows), not scored.
//  * A non-finite error (a result with a NaN pose) is stored as +infinity: a failure.
StatusOr<EvalReport> Evaluate(const Dataset& dataset, const std::vector<PoseResult>& results,
                              const std::vector<Detection>* detections,
                              const EvalOptions& options) {
  if (!(options.auc_max_m > 0.0) || !std::isfinite(options.auc_max_m)) {
    return InvalidArgument("EvalOptions.auc_max_m must be finite and > 0, got " +
                           std::to_string(options.auc_max_m));
  }

  // The rows of each (scene_id, im_id, obj_id), highest score first (ties: file order).
  std::map<ResultKey, std::vector<const PoseResult*>> rows_of;
  for (const PoseResult& r : results) rows_of[ResultKey{r.scene_id, r.im_id, r.obj_id}].push_back(&r);
  for (auto& [key, rows] : rows_of)
    std::stable_sort(rows.begin(), rows.end(), [](const PoseResult* a, const PoseResult* b) { return a->score > b->score; });

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
  const auto points_of = [&](int obj_id) -> StatusOr<const std::vector<Eigen::Vector3f>*> {
    auto points = eval_points.find(obj_id);
    if (points == eval_points.end()) {
      MCPOSE_ASSIGN_OR_RETURN(std::vector<Eigen::Vector3f> loaded, dataset.LoadEvalPoints(obj_id));
      if (loaded.empty())
        return InvalidArgument("no evaluation points for obj_id " + std::to_string(obj_id) + " (" +
                               dataset.ObjectName(obj_id) + ") in " + dataset.root());
      points = eval_points.emplace(obj_id, std::move(loaded)).first;
    }
    return &points->second;
  };
  for (const FrameKey& key : frames) {
    MCPOSE_ASSIGN_OR_RETURN(const Frame frame, dataset.LoadFrame(key));
    // Targets: instances with at least one visible pixel.
    std::vector<std::pair<const GtInstance*, int>> targets;  // with their visible pixels
    std::map<int, std::vector<size_t>> targets_of_class;     // indices into targets
    for (const GtInstance& gt : frame.gt) {
      MCPOSE_ASSIGN_OR_RETURN(const MaskImage mask, dataset.LoadVisibleMask(key, gt));
      const int visible = CountNonZero(mask);
      if (visible == 0) continue;
      targets_of_class[gt.obj_id].push_back(targets.size());
      targets.emplace_back(&gt, visible);
    }
    // Each target's row: the best row alone, or the rows in score order matched greedily.
    std::vector<const PoseResult*> row_of(targets.size(), nullptr);
    for (const auto& [obj_id, indices] : targets_of_class) {
      const auto rows = rows_of.find(ResultKey{key.scene_id, key.image_id, obj_id});
      if (rows == rows_of.end()) continue;
      matched.insert(rows->first);
      if (indices.size() == 1) {
        row_of[indices.front()] = rows->second.front();
        continue;
      }
      MCPOSE_ASSIGN_OR_RETURN(const std::vector<Eigen::Vector3f>* points, points_of(obj_id));
      for (const PoseResult* row : rows->second) {
        size_t nearest = targets.size();
        double nearest_m = INFINITY;
        for (size_t t : indices) {
          if (row_of[t]) continue;
          const double e = FiniteOrInfinity(AddS(*points, row->T_cam_obj, targets[t].first->T_cam_obj));
          if (nearest == targets.size() || e < nearest_m) nearest = t, nearest_m = e;
        }
        if (nearest == targets.size()) break;  // every instance has its row
        row_of[nearest] = row;
      }
    }
    for (size_t t = 0; t < targets.size(); ++t) {
      const GtInstance& gt = *targets[t].first;
      InstanceEval e;
      e.key = key;
      e.obj_id = gt.obj_id;
      e.gt_index = gt.gt_index;
      e.visible_pixels = targets[t].second;
      if (!row_of[t]) {
        e.add_m = e.adds_m = e.add_or_adds_m = INFINITY;
      } else {
        MCPOSE_ASSIGN_OR_RETURN(const std::vector<Eigen::Vector3f>* points, points_of(gt.obj_id));
        const SE3& T_est = row_of[t]->T_cam_obj;
        e.has_result = true;
        e.result_index = static_cast<int>(row_of[t] - results.data());
        e.add_m = FiniteOrInfinity(Add(*points, T_est, gt.T_cam_obj));
        e.adds_m = FiniteOrInfinity(AddS(*points, T_est, gt.T_cam_obj));
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

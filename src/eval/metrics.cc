// ADD, ADD-S and the accuracy-threshold AUC of the YCB-Video protocol (PoseCNN).
//
// Everything is computed in double: the model points are float (metres), but a mean over a few
// thousand distances of millimetres deserves more than 24 bits.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <tuple>
#include <set>
#include <vector>

#include <nanoflann.hpp>

#include "mcpose/eval.h"

namespace mcpose {
namespace {

// nanoflann dataset adaptor over posed points held in double.
struct PointCloudAdaptor {
  const std::vector<Eigen::Vector3d>& points;

  size_t kdtree_get_point_count() const { return points.size(); }
  double kdtree_get_pt(size_t index, size_t dim) const {
    return points[index][static_cast<Eigen::Index>(dim)];
  }
  // No precomputed bounding box: nanoflann computes it.
  template <class BBox>
  bool kdtree_get_bbox(BBox& /*bbox*/) const {
    return false;
  }
};

using KdTree = nanoflann::KDTreeSingleIndexAdaptor<
    nanoflann::L2_Simple_Adaptor<double, PointCloudAdaptor>, PointCloudAdaptor, 3, uint32_t>;

std::vector<Eigen::Vector3d> Transform(const std::vector<Eigen::Vector3f>& points_m,
                                       const SE3& T) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(points_m.size());
  for (const auto& p : points_m) out.push_back(T * p.cast<double>());
  return out;
}

// The distinct points of `points_m` and how often each occurs, or nothing when every point is
// distinct (the real points files). A KD-tree over points that repeat (a file with each point
// written hundreds of times) cannot split them and searches whole runs of equal points; over the
// distinct ones every search stays O(log n), so ADD-S costs O(n log n) in the distinct points.
struct Multiset {
  std::vector<Eigen::Vector3f> points;
  std::vector<double> count;
};
std::optional<Multiset> RepeatedPoints(const std::vector<Eigen::Vector3f>& points_m) {
  const auto less = [](const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
    return std::tie(a.x(), a.y(), a.z()) < std::tie(b.x(), b.y(), b.z());
  };
  std::vector<Eigen::Vector3f> sorted = points_m;
  std::sort(sorted.begin(), sorted.end(), less);
  if (std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end()) return std::nullopt;
  Multiset m;
  for (const Eigen::Vector3f& p : sorted) {
    if (!m.points.empty() && m.points.back() == p) {
      m.count.back() += 1;
    } else {
      m.points.push_back(p);
      m.count.push_back(1);
    }
  }
  return m;
}

}  // namespace

// An empty point set gives 0 (there is no point to be wrong about); Evaluate rejects empty
// eval point sets before it gets here.
double Add(const std::vector<Eigen::Vector3f>& points_m, const SE3& T_est, const SE3& T_gt) {
  if (points_m.empty()) return 0.0;
  double sum = 0.0;
  for (const auto& p_f : points_m) {
    const Eigen::Vector3d p = p_f.cast<double>();
    sum += (T_est * p - T_gt * p).norm();
  }
  return sum / static_cast<double>(points_m.size());
}

double AddS(const std::vector<Eigen::Vector3f>& points_m, const SE3& T_est, const SE3& T_gt) {
  if (points_m.empty()) return 0.0;
  // A non-finite pose would make the KD-tree split on NaN; its error is undefined anyway.
  if (!T_est.R.allFinite() || !T_est.t.allFinite() || !T_gt.R.allFinite() ||
      !T_gt.t.allFinite()) {
    return INFINITY;
  }

  if (const std::optional<Multiset> repeated = RepeatedPoints(points_m)) {
    // Each distinct point once, weighted by how often it occurs: the same mean.
    const std::vector<Eigen::Vector3d> est = Transform(repeated->points, T_est);
    const PointCloudAdaptor adaptor{est};
    const KdTree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(/*leaf_max_size=*/10));
    double sum = 0.0;
    for (size_t i = 0; i < repeated->points.size(); ++i) {
      const Eigen::Vector3d q = T_gt * repeated->points[i].cast<double>();
      uint32_t index = 0;
      double dist_sq = 0.0;
      tree.knnSearch(q.data(), 1, &index, &dist_sq);
      sum += repeated->count[i] * std::sqrt(dist_sq);
    }
    return sum / static_cast<double>(points_m.size());
  }
  // KD-tree over the estimate-posed points.
  const std::vector<Eigen::Vector3d> est = Transform(points_m, T_est);
  const PointCloudAdaptor adaptor{est};
  const KdTree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(/*leaf_max_size=*/10));

  // Mean distance from each ground-truth-posed point to its nearest estimate-posed point.
  double sum = 0.0;
  for (const auto& p_f : points_m) {
    const Eigen::Vector3d q = T_gt * p_f.cast<double>();
    uint32_t index = 0;
    double dist_sq = 0.0;
    tree.knnSearch(q.data(), 1, &index, &dist_sq);
    sum += std::sqrt(dist_sq);
  }
  return sum / static_cast<double>(points_m.size());
}

// acc(x) is a step function that rises by 1/n at each error e_i (acc(x) counts e_i < x), so
// the area under it on [0, max] is exactly sum_i (max - clamp(e_i, 0, max)) / n. Divided by max
// and summed over the errors below max only, it reads (n_below - sum_below e_i / max) / n, which
// is exactly 1 when every error is 0 and exactly 0 when none is below max.
// Non-finite errors (missing results) never count; a non-positive max_m gives 0.
double AccuracyAuc(const std::vector<double>& errors_m, double max_m) {
  if (errors_m.empty() || !(max_m > 0.0) || !std::isfinite(max_m)) return 0.0;
  double below = 0.0, sum_below_m = 0.0;
  for (double e : errors_m) {
    if (!(e < max_m)) continue;  // also skips NaN
    below += 1.0;
    sum_below_m += std::max(e, 0.0);
  }
  return (below - sum_below_m / max_m) / static_cast<double>(errors_m.size());
}

std::set<int> YcbvSymmetricObjectIds() { return {13, 16, 19, 20, 21}; }

}  // namespace mcpose

#include "score/box_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mcpose::score {

std::vector<Eigen::Vector3d> ExtremePoints(const Mesh& mesh) {
  std::vector<Eigen::Vector3d> out;
  if (mesh.vertices_m.empty()) return out;
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz) {
        if (dx == 0 && dy == 0 && dz == 0) continue;
        const Eigen::Vector3f d(static_cast<float>(dx), static_cast<float>(dy), static_cast<float>(dz));
        size_t best = 0;
        float best_dot = mesh.vertices_m[0].dot(d);
        for (size_t v = 1; v < mesh.vertices_m.size(); ++v) {
          const float dot = mesh.vertices_m[v].dot(d);
          if (dot > best_dot) best_dot = dot, best = v;
        }
        out.push_back(mesh.vertices_m[best].cast<double>());
      }
  return out;
}

FitBox FitBoxOf(const Detection& d, const Intrinsics& K) {
  constexpr double kOpen = std::numeric_limits<double>::infinity();
  constexpr double kBorder = 1.0;  // a side within a pixel of the image's edge is at the edge
  FitBox b{d.x, d.y, d.x + d.w, d.y + d.h};
  if (b.x0 <= kBorder) b.x0 = -kOpen;
  if (b.y0 <= kBorder) b.y0 = -kOpen;
  if (b.x1 >= K.width - kBorder) b.x1 = kOpen;
  if (b.y1 >= K.height - kBorder) b.y1 = kOpen;
  return b;
}

double BoxFitShare(std::span<const Eigen::Vector3d> extremes, const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
                   const Intrinsics& K, const FitBox& box) {
  constexpr double kNear = 0.05;
  double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
  for (const Eigen::Vector3d& p : extremes) {
    const Eigen::Vector3d c = R * p + t;
    if (!(c.z() > kNear)) return 0.0;
    const double u = K.fx * c.x() / c.z() + K.cx, v = K.fy * c.y() / c.z() + K.cy;
    x0 = std::min(x0, u), x1 = std::max(x1, u), y0 = std::min(y0, v), y1 = std::max(y1, v);
  }
  const double area = (x1 - x0) * (y1 - y0);
  if (!(area > 0)) return 1.0;
  const double w = std::max(0.0, std::min(x1, box.x1) - std::max(x0, box.x0));
  const double h = std::max(0.0, std::min(y1, box.y1) - std::max(y0, box.y0));
  return w * h / area;
}

}  // namespace mcpose::score

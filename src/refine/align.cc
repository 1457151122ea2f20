#include "refine/align.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Cholesky>

namespace mcpose::refine {

namespace {

// Observed points and normals of the box, camera frame; normal zero where it cannot be had.
struct ObservedSurface {
  render::PixelRect box;
  std::vector<Eigen::Vector3f> point, normal;
  const Eigen::Vector3f* At(int x, int y, const Eigen::Vector3f** n) const {
    const size_t i = static_cast<size_t>(y - box.y0) * box.width() + (x - box.x0);
    *n = &normal[i];
    return &point[i];
  }
};

Eigen::Vector3f BackProject(const Intrinsics& K, double x, double y, float z) {
  return {static_cast<float>((x - K.cx) / K.fx) * z, static_cast<float>((y - K.cy) / K.fy) * z, z};
}

ObservedSurface Observe(const Intrinsics& K, const DepthImage& depth, const render::PixelRect& box) {
  ObservedSurface s;
  s.box = box;
  const size_t n = static_cast<size_t>(box.area());
  s.point.assign(n, Eigen::Vector3f::Zero());
  s.normal.assign(n, Eigen::Vector3f::Zero());
  constexpr int kStep = 2;            // neighbours this many pixels away: less sensor noise
  constexpr float kMaxJump = 0.02f;   // a larger depth step is an edge, not a surface
  auto z_at = [&](int x, int y) { return x < 0 || y < 0 || x >= depth.width || y >= depth.height ? 0.f : depth.at(x, y); };
  for (int y = box.y0; y < box.y1; ++y) {
    for (int x = box.x0; x < box.x1; ++x) {
      const size_t i = static_cast<size_t>(y - box.y0) * box.width() + (x - box.x0);
      const float z = z_at(x, y);
      if (!(z > 0)) continue;
      s.point[i] = BackProject(K, x, y, z);
      const float zl = z_at(x - kStep, y), zr = z_at(x + kStep, y), zu = z_at(x, y - kStep), zd = z_at(x, y + kStep);
      if (!(zl > 0 && zr > 0 && zu > 0 && zd > 0)) continue;
      if (std::fabs(zl - z) > kMaxJump || std::fabs(zr - z) > kMaxJump || std::fabs(zu - z) > kMaxJump ||
          std::fabs(zd - z) > kMaxJump)
        continue;
      const Eigen::Vector3f dx = BackProject(K, x + kStep, y, zr) - BackProject(K, x - kStep, y, zl);
      const Eigen::Vector3f dy = BackProject(K, x, y + kStep, zd) - BackProject(K, x, y - kStep, zu);
      Eigen::Vector3f nrm = dx.cross(dy);
      if (!(nrm.squaredNorm() > 0)) continue;
      nrm.normalize();
      if (nrm.dot(s.point[i]) > 0) nrm = -nrm;  // facing the camera
      s.normal[i] = nrm;
    }
  }
  return s;
}

// The model points the mesh shows in the box at pose T (model frame), at most max_points of
// them, an even subsample of the rendered pixels.
std::vector<Eigen::Vector3f> VisibleModelPoints(const Intrinsics& K, const render::PixelRect& box, const Mesh& mesh,
                                                const SE3& T, int max_points) {
  render::RasterParams p;
  p.fx = static_cast<float>(K.fx), p.fy = static_cast<float>(K.fy);
  p.cx = static_cast<float>(K.cx), p.cy = static_cast<float>(K.cy);
  p.box = box;
  std::vector<render::ScreenVertex> sv(mesh.vertices_m.size());
  render::ProjectVertices(mesh.vertices_m, T.R.cast<float>(), T.t.cast<float>(), p, sv);
  std::vector<float> z(static_cast<size_t>(box.area()), INFINITY);
  render::RasterizeDepthReference(sv, mesh.triangles, p, z.data(), nullptr);
  std::vector<size_t> drawn;
  for (size_t i = 0; i < z.size(); ++i)
    if (z[i] != INFINITY) drawn.push_back(i);
  const size_t every = std::max<size_t>(1, (drawn.size() + max_points - 1) / std::max(1, max_points));
  const SE3 T_obj_cam = T.Inverse();
  std::vector<Eigen::Vector3f> out;
  for (size_t k = 0; k < drawn.size(); k += every) {
    const size_t i = drawn[k];
    const int x = box.x0 + static_cast<int>(i % box.width()), y = box.y0 + static_cast<int>(i / box.width());
    out.push_back((T_obj_cam * BackProject(K, x, y, z[i]).cast<double>()).cast<float>());
  }
  return out;
}

// The normal equations H, g of the robust point-to-plane residuals of the model points at pose
// T, and their weighted RMS; returns the number of pairs. Residual r = n . (p - q) of model
// point p (camera frame) and observed point q with normal n; a step (dt, dw) moves p by
// dt + dw x p, so J = [n^T, (p x n)^T].
int Linearize(const Intrinsics& K, const render::PixelRect& box, const ObservedSurface& observed,
              const std::vector<Eigen::Vector3f>& model, const SE3& T, const AlignOptions& o,
              Eigen::Matrix<double, 6, 6>* H_out, Eigen::Matrix<double, 6, 1>* g_out, double* rms) {
  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
  double sum_w = 0, sum_wr2 = 0;
  int pairs = 0;
  const Eigen::Matrix3f R = T.R.cast<float>();
  const Eigen::Vector3f t = T.t.cast<float>();
  for (const Eigen::Vector3f& pm : model) {
    const Eigen::Vector3f p = R * pm + t;
    if (!(p.z() > 0.05f)) continue;
    const long x = std::lround(K.fx * p.x() / p.z() + K.cx), y = std::lround(K.fy * p.y() / p.z() + K.cy);
    if (x < box.x0 || y < box.y0 || x >= box.x1 || y >= box.y1) continue;
    const Eigen::Vector3f* n = nullptr;
    const Eigen::Vector3f& q = *observed.At(static_cast<int>(x), static_cast<int>(y), &n);
    if (!(q.z() > 0) || n->isZero()) continue;
    if (q.z() < p.z() - o.occlusion_m) continue;  // hidden behind something else
    const Eigen::Vector3f d = p - q;
    if (d.norm() > o.max_distance_m) continue;
    const double r = n->dot(d);
    const double u = r / o.tukey_m;
    if (std::fabs(u) >= 1) continue;
    const double w = (1 - u * u) * (1 - u * u);
    Eigen::Matrix<double, 6, 1> J;
    J.head<3>() = n->cast<double>();
    J.tail<3>() = p.cast<double>().cross(n->cast<double>());
    H += w * J * J.transpose();
    g += w * J * r;
    sum_w += w, sum_wr2 += w * r * r;
    ++pairs;
  }
  *H_out = H, *g_out = g;
  *rms = sum_w > 0 ? std::sqrt(sum_wr2 / sum_w) : 0.0;
  return pairs;
}

}  // namespace

AlignResult AlignToDepth(const Intrinsics& K, const DepthImage& depth, const render::PixelRect& box, const Mesh& mesh,
                         const SE3& T0, const AlignOptions& o) {
  AlignResult result;
  result.T_cam_obj = T0;
  if (box.empty()) return result;
  const ObservedSurface observed = Observe(K, depth, box);
  std::vector<Eigen::Vector3f> model;
  SE3 T = T0;
  double lambda = 1e-4;  // Levenberg-Marquardt damping, relative to the Hessian's diagonal
  for (int it = 0; it < o.max_iterations; ++it) {
    if (it % std::max(1, o.rerender_every) == 0) model = VisibleModelPoints(K, box, mesh, T, o.max_points);

    // ---- Pairs, robust weights, the normal equations of one Gauss-Newton step --------------
    Eigen::Matrix<double, 6, 6> H;
    Eigen::Matrix<double, 6, 1> g;
    double rms = 0;
    const int pairs = Linearize(K, box, observed, model, T, o, &H, &g, &rms);
    result.pairs = pairs;
    if (pairs < o.min_points) break;
    if (it == 0) result.rms_before_m = rms;

    // ---- The damped step, applied on the left in the camera frame ---------------------------
    Eigen::Matrix<double, 6, 6> A = H;
    A.diagonal() *= 1 + lambda;
    const Eigen::Matrix<double, 6, 1> step = A.ldlt().solve(-g);
    if (!step.allFinite()) break;
    const Eigen::Matrix3d dR = ExpSO3(step.tail<3>());
    T = SE3(dR * T.R, dR * T.t + step.head<3>());
    result.path.push_back(T);
    result.iterations = it + 1;
    result.moved = true;
    if (step.head<3>().norm() < o.min_step && step.tail<3>().norm() < o.min_step) break;
  }
  result.T_cam_obj = T;
  if (result.moved) {  // the residual where the steps ended
    Eigen::Matrix<double, 6, 6> H;
    Eigen::Matrix<double, 6, 1> g;
    result.pairs = Linearize(K, box, observed, model, T, o, &H, &g, &result.rms_after_m);
  } else {
    result.rms_after_m = result.rms_before_m;
  }
  return result;
}

}  // namespace mcpose::refine

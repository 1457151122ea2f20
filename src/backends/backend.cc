#include "backends/backend.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"

namespace mcpose::backends::steps {

std::span<render::ScreenVertex> Prepare(const BoxTarget& box, Scratch* scratch) {
  const size_t n = box.mesh->vertices_m.size();
  if (scratch->vertices.size() < n) scratch->vertices.resize(n);
  const size_t pixels = static_cast<size_t>(box.observed->rect.area()) + render::kSimdPadFloats;
  if (scratch->zbuf.size() < pixels) scratch->zbuf.resize(pixels);
  return {scratch->vertices.data(), n};
}

render::PixelRect RelativeCover(const score::BoxObservation& box, const render::PixelRect& cover, InlierMode mode) {
  const render::PixelRect c = mode == InlierMode::k3D ? box.rect : cover;
  if (c.empty()) return render::PixelRect{};
  return render::PixelRect{c.x0 - box.rect.x0, c.y0 - box.rect.y0, c.x1 - box.rect.x0, c.y1 - box.rect.y0};
}

void ClearScalar(float* zbuf, int stride, const render::PixelRect& rel) {
  for (int y = rel.y0; y < rel.y1; ++y) std::fill_n(zbuf + static_cast<size_t>(y) * stride + rel.x0, rel.width(), INFINITY);
}

score::InlierCounts Count(const BoxTarget& target, const float* zbuf, const render::PixelRect& rel,
                          const Eigen::Matrix3f& R, const Eigen::Vector3f& t, const SampleSettings& settings,
                          bool simd) {
  const score::BoxObservation& box = *target.observed;
  const int stride = box.rect.width();
  score::InlierCounts counts;
  if (settings.inlier_mode == InlierMode::k3D) {
    counts = box.cloud->CountInliers3D(std::span<const float>(zbuf, static_cast<size_t>(box.rect.area())), settings.eps_m);
  } else if (simd) {
    counts = score::CountInliers1DInRectSimd(zbuf, box.observed_or_nan.data(), stride, rel, box.n_observed, settings.eps_m);
  } else {
    counts = score::CountInliers1DInRect(zbuf, box.observed.data(), stride, rel, box.n_observed, settings.eps_m);
  }
  if (target.colour) counts.colour = CountColour(target, zbuf, rel, R, t, settings, simd);
  return counts;
}

score::ColourStats CountColour(const BoxTarget& target, const float* zbuf, const render::PixelRect& rel,
                               const Eigen::Matrix3f& R, const Eigen::Vector3f& t, const SampleSettings& settings,
                               bool simd) {
  const score::BoxObservation& box = *target.observed;
  const int stride = box.rect.width();
  // The colour of the depth inliers: camera to model is (R^T, -R^T t).
  score::ColourSample c;
  c.rendered = zbuf;
  c.observed = box.observed.data(), c.observed_or_nan = box.observed_or_nan.data();
  c.observed_rgba = box.observed_rgba.data();
  c.stride = stride;
  c.rect = rel;
  c.eps_m = settings.eps_m;
  c.step = settings.colour_step;
  c.grid_x0 = static_cast<float>(box.rect.x0), c.grid_y0 = static_cast<float>(box.rect.y0);
  c.cx = static_cast<float>(box.K_grid.cx), c.cy = static_cast<float>(box.K_grid.cy);
  c.inv_fx = static_cast<float>(1.0 / box.K_grid.fx), c.inv_fy = static_cast<float>(1.0 / box.K_grid.fy);
  const Eigen::Matrix3f Rt = R.transpose();
  const Eigen::Vector3f tm = -(Rt * t);
  for (int i = 0; i < 9; ++i) c.R_model_cam[i] = Rt(i / 3, i % 3);
  for (int a = 0; a < 3; ++a) c.t_model_cam[a] = tm[a];
  return simd ? score::CountColourSimd(c, *target.colour) : score::CountColour(c, *target.colour);
}

size_t CheckHardwareInputs(const BoxTarget& box, const SampleSettings& settings) {
  const size_t area = static_cast<size_t>(box.observed->rect.area());
  // The engine checks these before it scores (options and engine/box_scorer.cc).
  MCPOSE_CHECK(settings.inlier_mode == InlierMode::k1D && box.observed->depth_bounds.size() == area &&
               box.hw_model && box.hw_model->size() == box.mesh->vertices_m.size());
  return area;
}

score::InlierCounts HardwareCounts(const hw::Counts& c, const score::BoxObservation& box) {
  score::InlierCounts counts;
  counts.inliers = c.inliers, counts.rendered = c.rendered, counts.occluded = c.occluded;
  counts.observed = box.n_observed;
  return counts;
}

void CountHardwareColour(const BoxTarget& box, std::span<const uint32_t> hw_zbuf, const Eigen::Matrix3f& R,
                         const Eigen::Vector3f& t, const SampleSettings& settings, Scratch* scratch,
                         score::InlierCounts* counts) {
  const score::BoxObservation& obs = *box.observed;
  const size_t area = hw_zbuf.size();
  scratch->zbuf.resize(std::max(scratch->zbuf.size(), area + render::kSimdPadFloats));
  for (size_t i = 0; i < area; ++i) scratch->zbuf[i] = hw::DepthMetres(hw_zbuf[i]);
  const render::PixelRect whole{0, 0, obs.rect.width(), obs.rect.height()};
  counts->colour = CountColour(box, scratch->zbuf.data(), whole, R, t, settings, /*simd=*/false);
}

}  // namespace mcpose::backends::steps

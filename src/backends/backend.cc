#include "backends/backend.h"

#include <algorithm>
#include <cmath>

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

score::InlierCounts Count(const score::BoxObservation& box, const float* zbuf, const render::PixelRect& rel,
                          const SampleSettings& settings, bool simd) {
  const int stride = box.rect.width();
  if (settings.inlier_mode == InlierMode::k3D)
    return box.cloud->CountInliers3D(std::span<const float>(zbuf, static_cast<size_t>(box.rect.area())), settings.eps_m);
  if (simd)
    return score::CountInliers1DInRectSimd(zbuf, box.observed_or_nan.data(), stride, rel, box.n_observed, settings.eps_m);
  return score::CountInliers1DInRect(zbuf, box.observed.data(), stride, rel, box.n_observed, settings.eps_m);
}

}  // namespace mcpose::backends::steps

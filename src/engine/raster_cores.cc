#include "engine/raster_cores.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"
#include "render/raster_fixed.h"

namespace mcpose::engine {

render::PixelRect ClipBox(double x, double y, double w, double h, int width, int height) {
  render::PixelRect r;
  // BOP boxes count pixel indices: [x, x + w) holds pixels x .. x + w - 1. Fractional
  // boxes are rounded outwards.
  r.x0 = static_cast<int>(std::max(0.0, std::floor(x)));
  r.y0 = static_cast<int>(std::max(0.0, std::floor(y)));
  r.x1 = static_cast<int>(std::min<double>(width, std::ceil(x + w)));
  r.y1 = static_cast<int>(std::min<double>(height, std::ceil(y + h)));
  if (r.empty()) return render::PixelRect{};
  return r;
}

BoxDepth DistributeDepth(const DepthImage& depth, const Intrinsics& K, const render::PixelRect& rect,
                         double score, InlierMode mode) {
  BoxDepth b;
  b.rect = rect;
  b.score = score;
  b.observed.resize(static_cast<size_t>(rect.area()));
  for (int y = rect.y0; y < rect.y1; ++y) {
    const float* src = depth.depth_m.data() + static_cast<size_t>(y) * depth.width + rect.x0;
    std::copy(src, src + rect.width(), b.observed.data() + static_cast<size_t>(y - rect.y0) * rect.width());
  }
  b.n_observed = score::CountObserved(b.observed);
  if (mode == InlierMode::k3D) b.cloud = std::make_unique<score::ObservedCloud>(K, rect, b.observed);
  return b;
}

int64_t UnionArea(std::span<const render::PixelRect> rects) {
  if (rects.empty()) return 0;
  int x0 = rects[0].x0, y0 = rects[0].y0, x1 = rects[0].x1, y1 = rects[0].y1;
  for (const auto& r : rects) {
    x0 = std::min(x0, r.x0), y0 = std::min(y0, r.y0), x1 = std::max(x1, r.x1), y1 = std::max(y1, r.y1);
  }
  const int w = x1 - x0;
  std::vector<char> covered(static_cast<size_t>(w) * (y1 - y0), 0);
  for (const auto& r : rects)
    for (int y = r.y0; y < r.y1; ++y) std::fill_n(covered.begin() + (y - y0) * w + (r.x0 - x0), r.width(), 1);
  return std::count(covered.begin(), covered.end(), 1);
}

RasterCores::RasterCores(int threads, RasterBackend backend)
    : pool_(threads), backend_(backend), scratch_(pool_.size()) {}

RasterCores::~RasterCores() = default;

void RasterCores::Score(const ScoreJob& job, const filter::ParticleSet& particles,
                        std::span<score::InlierCounts> counts, render::RasterStats* stats) {
  MCPOSE_CHECK_EQ(counts.size(), particles.size());
  const auto& mesh = *job.mesh;
  for (auto& s : scratch_) {
    s.vertices.resize(mesh.vertices_m.size());
    s.stats = render::RasterStats{};
  }
  pool_.ParallelFor(static_cast<int64_t>(particles.size()), [&](int64_t begin, int64_t end, int worker) {
    Scratch& s = scratch_[worker];
    for (int64_t i = begin; i < end; ++i) {
      const BoxDepth& box = job.boxes[particles.box[i]];
      render::RasterParams params;
      params.fx = static_cast<float>(job.K.fx);
      params.fy = static_cast<float>(job.K.fy);
      params.cx = static_cast<float>(job.K.cx);
      params.cy = static_cast<float>(job.K.cy);
      params.box = box.rect;
      params.cull_backfaces = job.cull_backfaces;

      // Render the hypothesis into the box z-buffer.
      s.zbuf.assign(static_cast<size_t>(box.rect.area()), INFINITY);
      const Eigen::Matrix3f R = particles.R_cam_obj[i].cast<float>();
      const Eigen::Vector3f t = particles.t_cam_obj_m[i].cast<float>();
      switch (backend_) {
        case RasterBackend::kScalar:
          render::ProjectVertices(mesh.vertices_m, R, t, params, s.vertices);
          render::RasterizeDepthReference(s.vertices, mesh.triangles, params, s.zbuf.data(), &s.stats);
          break;
        case RasterBackend::kFixedPoint:
          render::ProjectVertices(mesh.vertices_m, R, t, params, s.vertices);
          render::RasterizeDepthFixedPoint(s.vertices, mesh.triangles, params, s.zbuf.data(), &s.stats);
          break;
      }

      // Compare with the observed depth of the box.
      counts[i] = job.inlier_mode == InlierMode::k1D
                      ? score::CountInliers1D(s.zbuf, box.observed, job.eps_m)
                      : box.cloud->CountInliers3D(s.zbuf, job.eps_m);
    }
  }, /*chunks_per_thread=*/16);
  if (stats)
    for (const auto& s : scratch_) *stats += s.stats;
}

}  // namespace mcpose::engine

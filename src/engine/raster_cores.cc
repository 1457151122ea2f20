#include "engine/raster_cores.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"
#include "render/raster_fixed.h"

namespace mcpose::engine {

render::PixelRect ClipBox(double x, double y, double w, double h, int width, int height) {
  render::PixelRect r;
  if (!(std::isfinite(x) && std::isfinite(y) && std::isfinite(w) && std::isfinite(h))) return r;
  // BOP boxes count pixel indices: [x, x + w) holds pixels x .. x + w - 1. Fractional
  // boxes are rounded outwards. Both ends are clamped to the image before the conversion to
  // int (a coordinate like 1e300 does not fit one).
  const auto clip = [](double v, int size) { return static_cast<int>(std::clamp(v, 0.0, static_cast<double>(size))); };
  r.x0 = clip(std::floor(x), width), r.x1 = clip(std::ceil(x + w), width);
  r.y0 = clip(std::floor(y), height), r.y1 = clip(std::ceil(y + h), height);
  if (r.empty()) return render::PixelRect{};
  return r;
}

BoxDepth DistributeDepth(const DepthImage& depth, const Intrinsics& K, const render::PixelRect& rect,
                         double score, InlierMode mode, int stride) {
  MCPOSE_CHECK_GE(stride, 1);
  BoxDepth b;
  b.image_rect = rect;
  b.stride = stride;
  const int gw = (rect.width() + stride - 1) / stride, gh = (rect.height() + stride - 1) / stride;
  b.rect = render::PixelRect{rect.x0, rect.y0, rect.x0 + gw, rect.y0 + gh};
  // Grid coordinate u_g = x0 + (u - x0) / s: the same projection, scaled about the box corner.
  b.K_grid = K;
  b.K_grid.fx = K.fx / stride;
  b.K_grid.fy = K.fy / stride;
  b.K_grid.cx = rect.x0 + (K.cx - rect.x0) / stride;
  b.K_grid.cy = rect.y0 + (K.cy - rect.y0) / stride;
  b.score = score;
  b.observed.resize(static_cast<size_t>(b.rect.area()));
  for (int j = 0; j < gh; ++j) {
    const float* src = depth.depth_m.data() + static_cast<size_t>(rect.y0 + j * stride) * depth.width + rect.x0;
    float* dst = b.observed.data() + static_cast<size_t>(j) * gw;
    for (int i = 0; i < gw; ++i) dst[i] = src[static_cast<size_t>(i) * stride];
  }
  b.n_observed = score::CountObserved(b.observed);
  b.observed_or_nan = score::ObservedOrNaN(b.observed);
  if (mode == InlierMode::k3D) b.cloud = std::make_unique<score::ObservedCloud>(b.K_grid, b.rect, b.observed);
  return b;
}

int BoxStride(const render::PixelRect& rect, const EstimatorOptions& options) {
  int s = std::max(1, options.pixel_stride);
  if (options.max_grid_pixels <= 0) return s;
  auto grid = [&](int k) { return int64_t{(rect.width() + k - 1) / k} * ((rect.height() + k - 1) / k); };
  while (grid(s) > options.max_grid_pixels && s < 16) ++s;
  return s;
}

int64_t UnionSamples(std::span<const BoxDepth* const> boxes) {
  if (boxes.empty()) return 0;
  render::PixelRect u = boxes[0]->image_rect;
  for (const BoxDepth* b : boxes) {
    const auto& r = b->image_rect;
    u.x0 = std::min(u.x0, r.x0), u.y0 = std::min(u.y0, r.y0), u.x1 = std::max(u.x1, r.x1), u.y1 = std::max(u.y1, r.y1);
  }
  const int w = u.width();
  std::vector<char> covered(static_cast<size_t>(u.area()), 0);
  for (const BoxDepth* b : boxes) {
    const auto& r = b->image_rect;
    for (int y = r.y0; y < r.y1; y += b->stride)
      for (int x = r.x0; x < r.x1; x += b->stride) covered[static_cast<size_t>(y - u.y0) * w + (x - u.x0)] = 1;
  }
  return std::count(covered.begin(), covered.end(), 1);
}

void SetEngineOptions(const EstimatorOptions& options, ScoreJob* job) {
  job->inlier_mode = options.inlier_mode;
  job->eps_m = static_cast<float>(options.eps_m);
  job->cull_backfaces = options.backface_culling;
  job->batched_setup = options.batched_setup;
}

RasterCores::RasterCores(int threads, RasterBackend backend)
    : pool_(threads), backend_(backend), scratch_(pool_.size()) {}

RasterCores::~RasterCores() = default;

void RasterCores::Score(const ScoreJob& job, const filter::ParticleSet& particles,
                        std::span<score::InlierCounts> counts, render::RasterStats* stats) {
  MCPOSE_CHECK_EQ(counts.size(), particles.size());
  MCPOSE_CHECK(job.box_mesh.empty() || job.box_mesh.size() == job.boxes.size());
  MCPOSE_CHECK(job.box_clusters.empty() || job.box_clusters.size() == job.box_mesh.size());
  size_t max_vertices = job.mesh->vertices_m.size();
  for (const Mesh* m : job.box_mesh) max_vertices = std::max(max_vertices, m->vertices_m.size());
  for (auto& s : scratch_) {
    s.vertices.resize(max_vertices);
    s.stats = render::RasterStats{};
  }
  // The simd and float-simd engines: the vertex stage, rows and inlier count of the Highway
  // kernels. The batched setup's snapped vertices (fixed, simd) come with the projection.
  const bool simd = backend_ == RasterBackend::kSimd || backend_ == RasterBackend::kFloatSimd;
  const bool fixed_point = backend_ == RasterBackend::kFixedPoint || backend_ == RasterBackend::kSimd;
  const bool snap = job.batched_setup && fixed_point;
  pool_.ParallelFor(static_cast<int64_t>(particles.size()), [&](int64_t begin, int64_t end, int worker) {
    Scratch& s = scratch_[worker];
    for (int64_t i = begin; i < end; ++i) {
      const BoxDepth& box = job.boxes[particles.box[i]];
      const Mesh& mesh = job.box_mesh.empty() ? *job.mesh : *job.box_mesh[particles.box[i]];
      const std::span<render::ScreenVertex> vertices(s.vertices.data(), mesh.vertices_m.size());
      render::RasterParams params;
      params.fx = static_cast<float>(box.K_grid.fx);
      params.fy = static_cast<float>(box.K_grid.fy);
      params.cx = static_cast<float>(box.K_grid.cx);
      params.cy = static_cast<float>(box.K_grid.cy);
      params.box = box.rect;
      params.cull_backfaces = job.cull_backfaces;

      // Project, then clear the z-buffer only where the mesh can land (the 3-D test reads the
      // whole box), render, and count inliers in that rect: the same counts as the whole box.
      const Eigen::Matrix3f R = particles.R_cam_obj[i].cast<float>();
      const Eigen::Vector3f t = particles.t_cam_obj_m[i].cast<float>();
      render::PixelRect cover;
      if (simd && snap) {
        cover = render::ProjectSnapBoundSimd(mesh.vertices_m, R, t, params, vertices, &s.snapped);
      } else if (simd) {
        render::ProjectVerticesSimd(mesh.vertices_m, R, t, params, vertices);
        cover = render::CoverBoundSimd(vertices, box.rect);
      } else {
        render::ProjectVertices(mesh.vertices_m, R, t, params, vertices);
        cover = render::CoverBound(vertices, box.rect);
        if (snap) render::SnapVertices(vertices, params, &s.snapped);
      }
      const int stride = box.rect.width();
      s.zbuf.resize(std::max(s.zbuf.size(), static_cast<size_t>(box.rect.area()) + render::kSimdPadFloats));
      if (job.inlier_mode == InlierMode::k3D) cover = box.rect;
      // Box-relative cover rect.
      const render::PixelRect rel =
          cover.empty() ? render::PixelRect{}
                        : render::PixelRect{cover.x0 - box.rect.x0, cover.y0 - box.rect.y0,
                                            cover.x1 - box.rect.x0, cover.y1 - box.rect.y0};
      if (simd) {
        render::ClearDepthRectSimd(s.zbuf.data(), stride, rel);
      } else {
        for (int y = rel.y0; y < rel.y1; ++y)
          std::fill_n(s.zbuf.data() + static_cast<size_t>(y) * stride + rel.x0, rel.width(), INFINITY);
      }
      switch (backend_) {
        case RasterBackend::kScalar:
          render::RasterizeDepthReference(vertices, mesh.triangles, params, s.zbuf.data(), &s.stats);
          break;
        case RasterBackend::kFloatSimd:
          render::RasterizeDepthFloatSimd(vertices, mesh.triangles, params, s.zbuf.data(), &s.stats);
          break;
        case RasterBackend::kFixedPoint:
        case RasterBackend::kSimd: {
          const render::RowKernel rows =
              simd ? render::RowKernel::kSimd : render::RowKernel::kScalar;
          const render::ClusterSet* clusters = job.box_clusters.empty() ? nullptr : job.box_clusters[particles.box[i]];
          render::SnappedVertices* snapped = snap ? &s.snapped : nullptr;
          if (!clusters) {
            render::RasterizeDepthFixedPoint(vertices, mesh.triangles, params, s.zbuf.data(), &s.stats, rows,
                                             snapped);
            break;
          }
          const Eigen::Vector3f camera_in_model = -(R.transpose() * t);
          // The simd engine decides a vector of clusters at a time; the same decisions.
          const size_t n_clusters = clusters->clusters.size();
          s.culls.resize(n_clusters);
          if (simd) {
            render::CullClustersSimd(*clusters, R, t, camera_in_model, params, s.culls.data());
          } else {
            for (size_t k = 0; k < n_clusters; ++k)
              s.culls[k] = render::CullCluster(clusters->clusters[k], R, t, camera_in_model, params);
          }
          // The kept clusters' triangles, in cluster order, go through one classification and
          // setup pass: runs of adjacent kept clusters are referenced in place, and copied
          // together only when a dropped cluster splits them.
          const std::span<const std::array<uint32_t, 3>> all(clusters->triangles);
          s.kept_triangles.clear();
          size_t run_first = 0, run_end = 0;  // the current run of kept triangles in `all`
          for (size_t k = 0; k < n_clusters; ++k) {
            const render::Cluster& c = clusters->clusters[k];
            switch (s.culls[k]) {
              case render::ClusterCull::kBackface:
                ++s.stats.clusters_culled_backface;
                s.stats.culled_backface += c.count;
                break;
              case render::ClusterCull::kOutsideBox:
                ++s.stats.clusters_culled_outside_box;
                s.stats.culled_outside_box += c.count;
                break;
              case render::ClusterCull::kKeep:
                if (run_end != c.first) {  // a new run: the previous one is copied out
                  s.kept_triangles.insert(s.kept_triangles.end(), all.begin() + run_first, all.begin() + run_end);
                  run_first = c.first;
                }
                run_end = c.first + c.count;
                continue;
            }
            s.stats.triangles += c.count;
          }
          s.stats.clusters += static_cast<int64_t>(n_clusters);
          std::span<const std::array<uint32_t, 3>> kept = all.subspan(run_first, run_end - run_first);
          if (!s.kept_triangles.empty()) {  // runs were copied out: the last one joins them
            s.kept_triangles.insert(s.kept_triangles.end(), kept.begin(), kept.end());
            kept = s.kept_triangles;
          }
          if (!kept.empty()) {
            render::RasterizeDepthFixedPoint(vertices, kept, params, s.zbuf.data(), &s.stats, rows, snapped);
          }
          break;
        }
      }

      // Compare with the observed depth of the box.
      if (job.inlier_mode == InlierMode::k1D) {
        counts[i] = simd
                        ? score::CountInliers1DInRectSimd(s.zbuf.data(), box.observed_or_nan.data(), stride, rel,
                                                          box.n_observed, job.eps_m)
                        : score::CountInliers1DInRect(s.zbuf.data(), box.observed.data(), stride, rel,
                                                      box.n_observed, job.eps_m);
      } else {
        counts[i] = box.cloud->CountInliers3D(
            std::span<const float>(s.zbuf.data(), static_cast<size_t>(box.rect.area())), job.eps_m);
      }
    }
  }, /*chunks_per_thread=*/16);
  if (stats)
    for (const auto& s : scratch_) *stats += s.stats;
}

}  // namespace mcpose::engine

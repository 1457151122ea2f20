// The fixed-point SIMD backend, the default engine: the fixed-point core (fixed_point.cc) with
// vertices projected and snapped, clusters culled, triangles set up, rows filled and inliers
// counted a Highway vector at a time (AVX-512, AVX2, SSE4 or scalar, chosen at run time):
// bit-identical to the fixed-point core.
#include "backends/backend.h"

namespace mcpose::backends {

namespace {

class FixedPointSimd final : public Backend {
 public:
  RasterBackend kind() const override { return RasterBackend::kSimd; }

  score::InlierCounts ScoreSample(const BoxTarget& box, const Eigen::Matrix3f& R, const Eigen::Vector3f& t,
                                  const SampleSettings& settings, Scratch* s,
                                  RasterCounters* stats) const override {
    const score::BoxObservation& obs = *box.observed;
    const render::RasterParams params = score::BoxRasterParams(obs, settings.cull_backfaces);
    const std::span<render::ScreenVertex> vertices = steps::Prepare(box, s);
    // Project, find the pixels the mesh can cover, and (batched setup) snap, in one pass.
    render::SnappedVertices* snapped = settings.batched_setup ? &s->snapped : nullptr;
    render::PixelRect cover;
    if (snapped) {
      cover = render::ProjectSnapBoundSimd(box.mesh->vertices_m, R, t, params, vertices, snapped);
    } else {
      render::ProjectVerticesSimd(box.mesh->vertices_m, R, t, params, vertices);
      cover = render::CoverBoundSimd(vertices, obs.rect);
    }
    const render::PixelRect rel = steps::RelativeCover(obs, cover, settings.inlier_mode);
    render::ClearDepthRectSimd(s->zbuf.data(), obs.rect.width(), rel);
    // Rasterize every triangle, or those of the clusters that survive culling (a vector of
    // clusters decided at a time).
    if (!box.clusters) {
      render::RasterizeDepthFixedPoint(vertices, box.mesh->triangles, params, s->zbuf.data(), stats,
                                       render::RowKernel::kSimd, snapped);
    } else {
      const render::ClusterSet& clusters = *box.clusters;
      s->culls.resize(clusters.clusters.size());
      render::CullClustersSimd(clusters, R, t, -(R.transpose() * t), params, s->culls.data());
      const auto kept = render::KeptTriangles(clusters, s->culls.data(), &s->kept_triangles, stats);
      if (!kept.empty())
        render::RasterizeDepthFixedPoint(vertices, kept, params, s->zbuf.data(), stats, render::RowKernel::kSimd,
                                         snapped);
    }
    // Count.
    return steps::Count(box, s->zbuf.data(), rel, R, t, settings, /*simd=*/true);
  }
};

}  // namespace

std::unique_ptr<Backend> MakeFixedPointSimd() { return std::make_unique<FixedPointSimd>(); }

}  // namespace mcpose::backends

// The fixed-point backend: vertices snapped to a 1/16-pixel grid, integer edge functions
// stepped from pixel to pixel, the 1/z plane through the snapped vertices (render/raster_fixed.h:
// the paper's sub-pixel quantization). Optionally drops whole culling clusters first and sets
// up triangles in batches (EngineOptions::cluster_culling, batched_setup).
#include "backends/backend.h"

namespace mcpose::backends {

namespace {

class FixedPoint final : public Backend {
 public:
  RasterBackend kind() const override { return RasterBackend::kFixedPoint; }

  score::InlierCounts ScoreSample(const BoxTarget& box, const Eigen::Matrix3f& R, const Eigen::Vector3f& t,
                                  const SampleSettings& settings, Scratch* s,
                                  RasterCounters* stats) const override {
    const score::BoxObservation& obs = *box.observed;
    const render::RasterParams params = score::BoxRasterParams(obs, settings.cull_backfaces);
    const std::span<render::ScreenVertex> vertices = steps::Prepare(box, s);
    // Project, find the pixels the mesh can cover, and snap the vertices for a batched setup.
    render::ProjectVertices(box.mesh->vertices_m, R, t, params, vertices);
    const render::PixelRect rel =
        steps::RelativeCover(obs, render::CoverBound(vertices, obs.rect), settings.inlier_mode);
    render::SnappedVertices* snapped = settings.batched_setup ? &s->snapped : nullptr;
    if (snapped) render::SnapVertices(vertices, params, snapped);
    steps::ClearScalar(s->zbuf.data(), obs.rect.width(), rel);
    // Rasterize every triangle, or those of the clusters that survive culling.
    if (!box.clusters) {
      render::RasterizeDepthFixedPoint(vertices, box.mesh->triangles, params, s->zbuf.data(), stats,
                                       render::RowKernel::kScalar, snapped);
    } else {
      const render::ClusterSet& clusters = *box.clusters;
      const Eigen::Vector3f camera_in_model = -(R.transpose() * t);
      s->culls.resize(clusters.clusters.size());
      for (size_t k = 0; k < clusters.clusters.size(); ++k)
        s->culls[k] = render::CullCluster(clusters.clusters[k], R, t, camera_in_model, params);
      const auto kept = render::KeptTriangles(clusters, s->culls.data(), &s->kept_triangles, stats);
      if (!kept.empty())
        render::RasterizeDepthFixedPoint(vertices, kept, params, s->zbuf.data(), stats, render::RowKernel::kScalar,
                                         snapped);
    }
    // Count.
    return steps::Count(box, s->zbuf.data(), rel, R, t, settings, /*simd=*/false);
  }
};

}  // namespace

std::unique_ptr<Backend> MakeFixedPoint() { return std::make_unique<FixedPoint>(); }

}  // namespace mcpose::backends

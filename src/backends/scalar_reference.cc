// The scalar reference backend: float vertices, a float edge-function test at every pixel
// centre of the triangle's bounding box (render/raster.cc). Simple and slow on purpose: every
// other backend is tested against it. Clusters are never used: it walks every triangle.
#include "backends/backend.h"

namespace mcpose::backends {

namespace {

class ScalarReference final : public Backend {
 public:
  RasterBackend kind() const override { return RasterBackend::kScalar; }

  score::InlierCounts ScoreSample(const BoxTarget& box, const Eigen::Matrix3f& R, const Eigen::Vector3f& t,
                                  const SampleSettings& settings, Scratch* s,
                                  RasterCounters* stats) const override {
    const score::BoxObservation& obs = *box.observed;
    const render::RasterParams params = score::BoxRasterParams(obs, settings.cull_backfaces);
    const std::span<render::ScreenVertex> vertices = steps::Prepare(box, s);
    // Project, and find the pixels the mesh can cover.
    render::ProjectVertices(box.mesh->vertices_m, R, t, params, vertices);
    const render::PixelRect rel =
        steps::RelativeCover(obs, render::CoverBound(vertices, obs.rect), settings.inlier_mode);
    // Rasterize into a z-buffer cleared only there.
    steps::ClearScalar(s->zbuf.data(), obs.rect.width(), rel);
    render::RasterizeDepthReference(vertices, box.mesh->triangles, params, s->zbuf.data(), stats);
    // Count.
    return steps::Count(box, s->zbuf.data(), rel, R, t, settings, /*simd=*/false);
  }
};

}  // namespace

std::unique_ptr<Backend> MakeScalarReference() { return std::make_unique<ScalarReference>(); }

}  // namespace mcpose::backends

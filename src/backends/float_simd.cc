// The float SIMD backend: the scalar reference reorganised for Highway vectors (vertices,
// triangle classification and pixels of a row a vector at a time, render/raster_float_simd.cc)
// with the reference's float operations in the reference's order: bit-identical z-buffers,
// counts and statistics. Clusters are never used: it walks every triangle.
#include "backends/backend.h"

namespace mcpose::backends {

namespace {

class FloatSimd final : public Backend {
 public:
  RasterBackend kind() const override { return RasterBackend::kFloatSimd; }

  score::InlierCounts ScoreSample(const BoxTarget& box, const Eigen::Matrix3f& R, const Eigen::Vector3f& t,
                                  const SampleSettings& settings, Scratch* s,
                                  RasterCounters* stats) const override {
    const score::BoxObservation& obs = *box.observed;
    const render::RasterParams params = score::BoxRasterParams(obs, settings.cull_backfaces);
    const std::span<render::ScreenVertex> vertices = steps::Prepare(box, s);
    // Project, and find the pixels the mesh can cover.
    render::ProjectVerticesSimd(box.mesh->vertices_m, R, t, params, vertices);
    const render::PixelRect rel =
        steps::RelativeCover(obs, render::CoverBoundSimd(vertices, obs.rect), settings.inlier_mode);
    // Rasterize into a z-buffer cleared only there.
    render::ClearDepthRectSimd(s->zbuf.data(), obs.rect.width(), rel);
    render::RasterizeDepthFloatSimd(vertices, box.mesh->triangles, params, s->zbuf.data(), stats);
    // Count.
    return steps::Count(box, s->zbuf.data(), rel, R, t, settings, /*simd=*/true);
  }
};

}  // namespace

std::unique_ptr<Backend> MakeFloatSimd() { return std::make_unique<FloatSimd>(); }

}  // namespace mcpose::backends

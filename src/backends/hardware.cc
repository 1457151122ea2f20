// The hardware backend: the paper's raster core in the integer numerics of the RTL (hw/,
// docs/hardware.md): the pose in Q1.16 and quarter depth units, one exact division per projected
// coordinate, the 1/z plane stepped in fixed point, an IZ z-buffer, and the depth distributor's
// inverse-depth bounds (score::BoxObservation::depth_bounds) in place of |z_r - z_o| < eps.
// Every triangle is walked (no clusters, no batching); the colour test, which the paper's
// hardware does not have, runs beside it on the z-buffer in metres.
#include "backends/backend.h"

namespace mcpose::backends {

namespace {

class Hardware final : public Backend {
 public:
  RasterBackend kind() const override { return RasterBackend::kHardware; }

  score::InlierCounts ScoreSample(const BoxTarget& box, const Eigen::Matrix3f& R, const Eigen::Vector3f& t,
                                  const SampleSettings& settings, Scratch* s,
                                  RasterCounters* stats) const override {
    const score::BoxObservation& obs = *box.observed;
    const size_t area = steps::CheckHardwareInputs(box, settings);
    const hw::Camera camera = score::BoxHardwareCamera(obs);
    s->hw_zbuf.resize(area);
    hw::CoreStats core;
    hw::RenderSample(*box.hw_model, box.mesh->triangles, hw::QuantizePose(R, t), camera, settings.cull_backfaces,
                     &s->hw_vertices, s->hw_zbuf, &core);
    const hw::Counts c = hw::CountBox(s->hw_zbuf, obs.depth_bounds);
    score::InlierCounts counts = steps::HardwareCounts(c, obs);
    if (stats) {
      stats->triangles_in += core.triangles;
      stats->triangles_rasterized += core.drawn;
      stats->fragments += core.fragments;
      stats->culled_near += core.near;
      stats->culled_degenerate += core.degenerate;
      stats->culled_backface += core.backface;
      stats->culled_outside_box += core.outside_box;
      stats->culled_between_pixels += core.between_pixels;
      stats->culled_hw_range += core.guard_band + core.too_large;
    }
    if (box.colour) steps::CountHardwareColour(box, s->hw_zbuf, R, t, settings, s, &counts);
    return counts;
  }
};

}  // namespace

std::unique_ptr<Backend> MakeHardware() { return std::make_unique<Hardware>(); }

}  // namespace mcpose::backends

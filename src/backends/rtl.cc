// The RTL backend: every sample through the raster core's RTL (hw/rtl/raster_core.sv) as
// Verilator compiles it (hw/rtl_core.h), clock by clock: the same inputs as the hw backend
// (hardware.cc) forms, so the same counts and z-buffer, bit for bit, some 150 times slower.
// Each raster core of the engine (each thread) drives its own simulated core, kept in its
// scratch; the box's bounds are written into it when they change. The RTL reports the triangles
// it drew and the pixels it covered, not why it left the others out.
#include "backends/backend.h"

#if MCPOSE_HAVE_RTL

#include "core/check.h"
#include "hw/rtl_core.h"

namespace mcpose::backends {

namespace {

class Rtl final : public Backend {
 public:
  RasterBackend kind() const override { return RasterBackend::kRtl; }

  score::InlierCounts ScoreSample(const BoxTarget& box, const Eigen::Matrix3f& R, const Eigen::Vector3f& t,
                                  const SampleSettings& settings, Scratch* s,
                                  RasterCounters* stats) const override {
    const score::BoxObservation& obs = *box.observed;
    const size_t area = steps::CheckHardwareInputs(box, settings);
    // The simulated core's memories (engine/box_scorer.cc refuses larger boxes and meshes).
    MCPOSE_CHECK(box.hw_model->size() <= (size_t{1} << hw::kRtlVertexIndexBits) &&
                 area <= (size_t{1} << hw::kRtlBoxWordBits));
    if (!s->rtl_core) s->rtl_core = std::make_shared<hw::RtlCore>();
    s->rtl_core->SetBounds(obs.depth_bounds);
    s->hw_zbuf.resize(area);
    hw::CoreStats core;
    const hw::Counts c = s->rtl_core->Run(hw::QuantizePose(R, t), score::BoxHardwareCamera(obs),
                                          settings.cull_backfaces, *box.hw_model, box.mesh->triangles, s->hw_zbuf,
                                          &core);
    score::InlierCounts counts = steps::HardwareCounts(c, obs);
    if (stats) {
      stats->triangles_in += core.triangles;
      stats->triangles_rasterized += core.drawn;
      stats->fragments += core.fragments;
    }
    if (box.colour) steps::CountHardwareColour(box, s->hw_zbuf, R, t, settings, s, &counts);
    return counts;
  }
};

}  // namespace

std::unique_ptr<Backend> MakeRtl() { return std::make_unique<Rtl>(); }

}  // namespace mcpose::backends

#endif  // MCPOSE_HAVE_RTL

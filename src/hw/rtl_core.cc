#include "hw/rtl_core.h"

#include <algorithm>

#include "Vraster_core.h"
#include "hw/rtl_driver.h"
#include "verilated.h"

namespace mcpose::hw {

// The core was verilated with these memories (CMakeLists.txt passes the same numbers).
static_assert(MCPOSE_RTL_AW == kRtlBoxWordBits && MCPOSE_RTL_VW == kRtlVertexIndexBits,
              "the Verilated core's AW and VW differ from hw/rtl_core.h's");

struct RtlCore::Impl {
  VerilatedContext context;  // one per model: models in different threads share nothing
  Vraster_core core{&context};
  rtl::CoreDriver<Vraster_core> driver{&core, kRtlVertexIndexBits};
};

RtlCore::RtlCore() : impl_(std::make_unique<Impl>()) {}
RtlCore::~RtlCore() = default;

void RtlCore::SetBounds(std::span<const DepthBounds> bounds) {
  if (std::equal(bounds.begin(), bounds.end(), loaded_.begin(), loaded_.end(),
                 [](const DepthBounds& a, const DepthBounds& b) { return a.lo == b.lo && a.hi == b.hi; }))
    return;
  impl_->driver.LoadBounds(bounds);
  loaded_.assign(bounds.begin(), bounds.end());
}

Counts RtlCore::Run(const Pose& pose, const Camera& camera, bool cull, std::span<const ModelVertex> model,
                    std::span<const std::array<uint32_t, 3>> triangles, std::span<uint32_t> zbuf, CoreStats* stats) {
  impl_->driver.Run(pose, camera, cull, model, triangles, zbuf);
  if (stats) {
    stats->triangles += static_cast<int64_t>(triangles.size());
    stats->drawn += impl_->driver.drawn();
    stats->fragments += impl_->driver.fragments();
  }
  return impl_->driver.counts();
}

}  // namespace mcpose::hw

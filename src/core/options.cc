#include <cmath>
#include <sstream>

#include "mcpose/options.h"
#include "mcpose/option_table.h"

namespace mcpose {

namespace {

bool Fail(std::string* error, const std::string& message) {
  if (error) *error = message;
  return false;
}

// The name of enum value `v` in `names`, and the value of `name` (false if none).
template <class Enum>
const char* NameOf(Enum v, std::span<const char* const> names) {
  const auto i = static_cast<size_t>(v);
  return i < names.size() ? names[i] : "unknown";
}
template <class Enum>
bool ValueOf(const std::string& name, std::span<const char* const> names, Enum* v) {
  for (size_t i = 0; i < names.size(); ++i)
    if (name == names[i]) {
      *v = static_cast<Enum>(i);
      return true;
    }
  return false;
}

}  // namespace

bool IsFixedPoint(RasterBackend backend) {
  return backend == RasterBackend::kFixedPoint || backend == RasterBackend::kSimd;
}

bool IsHardwareNumerics(RasterBackend backend) {
  return backend == RasterBackend::kHardware || backend == RasterBackend::kRtl;
}

bool RtlBackendAvailable() {
#if MCPOSE_HAVE_RTL
  return true;
#else
  return false;
#endif
}

const char* AppearanceOptions::SpaceName(Space space) { return NameOf(space, ColourSpaceNames()); }
bool AppearanceOptions::ParseSpace(const std::string& name, Space* space) {
  return ValueOf(name, ColourSpaceNames(), space);
}
bool ParseRasterBackend(const std::string& name, RasterBackend* backend) {
  return ValueOf(name, RasterBackendNames(), backend);
}
const char* RasterBackendName(RasterBackend backend) { return NameOf(backend, RasterBackendNames()); }

EngineOptions EngineOptions::Reference() {
  EngineOptions e;
  e.backend = RasterBackend::kScalar;
  e.pixel_stride = 1;
  e.max_grid_pixels = 0;
  e.lod_error_px = 0;
  e.DropUnusableFeatures();
  return e;
}

void EngineOptions::DropUnusableFeatures() {
  const bool lod = lod_error_px > 0;
  if (!lod) lod_unbiased = false;
  if (!lod || !IsFixedPoint(backend)) cluster_culling = false;
  if (!IsFixedPoint(backend)) batched_setup = false;
}

bool EstimatorOptions::IsValid(std::string* error) const {
  // Each field's bounds, from the table (include/mcpose/option_table.h), in its order.
  for (const OptionField& field : EstimatorOptionFields())
    if (const std::string problem = field.CheckBounds(*this); !problem.empty()) return Fail(error, problem);
  // Rules over several fields.
  if (std::fabs(weight.a + weight.b + weight.c - 1.0) > 1e-6) {
    std::ostringstream os;
    os << "weights must sum to 1 (a + b + c = " << weight.a + weight.b + weight.c << ")";
    return Fail(error, os.str());
  }
  if (static_cast<int64_t>(samples) * init.wide > limits::kMaxSamples) {
    std::ostringstream os;
    os << "samples * init.wide must be at most " << limits::kMaxSamples << " (the first generation), got " << samples
       << " * " << init.wide;
    return Fail(error, os.str());
  }
  if (resample.elite_share > resample.keep_top_fraction) {
    std::ostringstream os;
    os << "resample.elite_share (" << resample.elite_share << ") must not exceed resample.keep_top_fraction ("
       << resample.keep_top_fraction << "): the elite are the best of the kept samples";
    return Fail(error, os.str());
  }
  {
    const double steps = 360.0 / appearance.twin_step_deg;
    if (std::fabs(steps - std::round(steps)) > 1e-9) {
      std::ostringstream os;
      os << "appearance.twin_step_deg must divide 360, got " << appearance.twin_step_deg;
      return Fail(error, os.str());
    }
  }
  // Features that would have no effect: asking for them is a mistake the user should see.
  const std::string backend = RasterBackendName(engine.backend);
  if (engine.lod_unbiased && !(engine.lod_error_px > 0))
    return Fail(error, "engine.lod_unbiased has no effect with engine.lod_error_px 0 (no level of detail)");
  if (engine.cluster_culling && !(engine.lod_error_px > 0))
    return Fail(error, "engine.cluster_culling needs engine.lod_error_px > 0 (the clusters come with the LOD levels)");
  if (engine.cluster_culling && !IsFixedPoint(engine.backend))
    return Fail(error, "engine.cluster_culling needs a fixed-point engine.backend (fixed or simd), not " + backend);
  if (engine.batched_setup && !IsFixedPoint(engine.backend))
    return Fail(error, "engine.batched_setup needs a fixed-point engine.backend (fixed or simd), not " + backend);
  if (IsHardwareNumerics(engine.backend) && weight.inlier != InlierMode::k1D)
    return Fail(error, "engine.backend " + backend +
                           " counts 1-D inliers only (weight.inlier 1d), as the paper's hardware does");
  if (appearance.hue_first_levels > 0 && appearance.space != AppearanceOptions::Space::kIntensityHue)
    return Fail(error, std::string("appearance.hue_first_levels needs appearance.space intensity-hue, not ") +
                           AppearanceOptions::SpaceName(appearance.space));
  if (engine.backend == RasterBackend::kRtl && !RtlBackendAvailable())
    return Fail(error, "engine.backend rtl needs a build with Verilator (scripts/install_deps.sh installs it; "
                       "the build finds it when configured)");
  return true;
}

}  // namespace mcpose

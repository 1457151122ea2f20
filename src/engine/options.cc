#include <cmath>
#include <sstream>

#include "mcpose/options.h"

namespace mcpose {

namespace {

bool Fail(std::string* error, const std::string& message) {
  if (error) *error = message;
  return false;
}

}  // namespace

bool IsFixedPoint(RasterBackend backend) {
  return backend == RasterBackend::kFixedPoint || backend == RasterBackend::kSimd;
}

const char* AppearanceOptions::SpaceName(Space space) {
  switch (space) {
    case Space::kRgb: return "rgb";
    case Space::kChroma: return "chroma";
    case Space::kIntensityHue: return "intensity-hue";
  }
  return "intensity-hue";
}

bool AppearanceOptions::ParseSpace(const std::string& name, Space* space) {
  for (Space s : {Space::kRgb, Space::kChroma, Space::kIntensityHue})
    if (name == SpaceName(s)) {
      *space = s;
      return true;
    }
  return false;
}

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
  auto finite_nonnegative = [](double v) { return std::isfinite(v) && v >= 0; };
  if (samples < 1 || samples > limits::kMaxSamples)
    return Fail(error, "samples must lie in [1, " + std::to_string(limits::kMaxSamples) + "], got " +
                           std::to_string(samples));
  if (max_iterations < 1 || max_iterations > limits::kMaxIterations)
    return Fail(error, "max_iterations must lie in [1, " + std::to_string(limits::kMaxIterations) + "], got " +
                           std::to_string(max_iterations));
  if (!std::isfinite(tau)) return Fail(error, "tau must be finite");
  if (max_instances < 0 || max_instances > limits::kMaxBoxesPerImage)
    return Fail(error, "max_instances must lie in [0, " + std::to_string(limits::kMaxBoxesPerImage) + "], got " +
                           std::to_string(max_instances));

  if (!(init.depth_quantile >= 0 && init.depth_quantile <= 1))
    return Fail(error, "init.depth_quantile must lie in [0, 1]");
  if (!(init.front_share >= 0 && init.front_share <= 1)) return Fail(error, "init.front_share must lie in [0, 1]");
  if (!(init.front_quantile >= 0 && init.front_quantile <= 1))
    return Fail(error, "init.front_quantile must lie in [0, 1]");
  if (!(init.rest_share >= 0 && init.rest_share <= 1)) return Fail(error, "init.rest_share must lie in [0, 1]");
  if (!(finite_nonnegative(init.sigma_t_m) && init.sigma_t_m <= limits::kMaxSigmaM))
    return Fail(error, "init.sigma_t_m must lie in [0, 10] m");

  if (!(std::isfinite(weight.eps_m) && weight.eps_m > 0)) return Fail(error, "weight.eps_m must be finite and > 0");
  if (!(weight.box_fit >= 0 && weight.box_fit <= 1)) return Fail(error, "weight.box_fit must lie in [0, 1]");
  for (double w : {weight.a, weight.b, weight.c})
    if (!finite_nonnegative(w)) return Fail(error, "weights a, b, c must be finite and >= 0");
  if (std::fabs(weight.a + weight.b + weight.c - 1.0) > 1e-6) {
    std::ostringstream os;
    os << "weights must sum to 1 (a + b + c = " << weight.a + weight.b + weight.c << ")";
    return Fail(error, os.str());
  }

  if (!(resample.keep_top_fraction > 0 && resample.keep_top_fraction <= 1))
    return Fail(error, "resample.keep_top_fraction must lie in (0, 1]");
  if (resample.cdf_table_size < 1 || resample.cdf_table_size > limits::kMaxCdfTable)
    return Fail(error, "resample.cdf_table_size must lie in [1, " + std::to_string(limits::kMaxCdfTable) + "]");

  for (double s : {diffusion.sigma_t_m, diffusion.sigma_t_min_m})
    if (!(finite_nonnegative(s) && s <= limits::kMaxSigmaM))
      return Fail(error, "diffusion translation sigmas must lie in [0, 10] m");
  for (double s : {diffusion.sigma_r_rad, diffusion.sigma_r_min_rad})
    if (!(finite_nonnegative(s) && s <= limits::kMaxSigmaRad))
      return Fail(error, "diffusion rotation sigmas must lie in [0, 2 pi] rad");
  if (!(diffusion.anneal > 0 && diffusion.anneal <= 1)) return Fail(error, "diffusion.anneal must lie in (0, 1]");
  if (!(diffusion.flip_rate >= 0 && diffusion.flip_rate <= 1))
    return Fail(error, "diffusion.flip_rate must lie in [0, 1]");

  if (!(appearance.weight >= 0 && appearance.weight < 1)) return Fail(error, "appearance.weight must lie in [0, 1)");
  if (appearance.min_pixels < 2) return Fail(error, "appearance.min_pixels must be >= 2");
  if (appearance.pixel_step < 1 || appearance.pixel_step > 4) return Fail(error, "appearance.pixel_step must lie in [1, 4]");
  if (!(appearance.trust_pixels >= 0 && appearance.trust_pixels <= 1e6))
    return Fail(error, "appearance.trust_pixels must lie in [0, 1e6]");
  if (appearance.smooth_radius < 0 || appearance.smooth_radius > 3)
    return Fail(error, "appearance.smooth_radius must lie in [0, 3]");
  if (appearance.ramp_iterations < 0 || appearance.ramp_iterations > limits::kMaxIterations)
    return Fail(error, "appearance.ramp_iterations must lie in [0, " + std::to_string(limits::kMaxIterations) + "]");
  {
    const double steps = 360.0 / appearance.twin_step_deg;
    if (!(appearance.twin_step_deg >= 1 && appearance.twin_step_deg <= 180) ||
        std::fabs(steps - std::round(steps)) > 1e-9)
      return Fail(error, "appearance.twin_step_deg must divide 360 and lie in [1, 180]");
  }
  if (appearance.twin_refine_iterations < 0 || appearance.twin_refine_iterations > limits::kMaxIterations)
    return Fail(error, "appearance.twin_refine_iterations must lie in [0, " + std::to_string(limits::kMaxIterations) +
                           "]");
  if (!(appearance.twin_depth_margin >= 0 && appearance.twin_depth_margin <= 1))
    return Fail(error, "appearance.twin_depth_margin must lie in [0, 1]");

  if (refine.max_iterations < 0 || refine.twin_iterations < 0 || refine.max_iterations > limits::kMaxIterations ||
      refine.twin_iterations > limits::kMaxIterations)
    return Fail(error, "refine.max_iterations and refine.twin_iterations must lie in [0, " +
                           std::to_string(limits::kMaxIterations) + "]");
  if (!(std::isfinite(refine.tukey_m) && refine.tukey_m > 0)) return Fail(error, "refine.tukey_m must be > 0");
  if (!(std::isfinite(refine.max_distance_m) && refine.max_distance_m > 0))
    return Fail(error, "refine.max_distance_m must be > 0");
  if (!(std::isfinite(refine.accept_eps_m) && refine.accept_eps_m >= 0))
    return Fail(error, "refine.accept_eps_m must be >= 0 (0: weight.eps_m)");

  if (!finite_nonnegative(engine.lod_error_px))
    return Fail(error, "engine.lod_error_px must be finite and >= 0 (0 = full mesh)");
  if (engine.pixel_stride < 1 || engine.pixel_stride > 16)
    return Fail(error, "engine.pixel_stride must lie in [1, 16], got " + std::to_string(engine.pixel_stride));
  if (engine.max_grid_pixels < 0) return Fail(error, "engine.max_grid_pixels must be >= 0 (0 = no budget)");
  if (engine.threads < 0 || engine.threads > limits::kMaxThreads)
    return Fail(error, "engine.threads must lie in [0, " + std::to_string(limits::kMaxThreads) +
                           "] (0 = all hardware threads)");
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
  return true;
}

bool ParseRasterBackend(const std::string& name, RasterBackend* backend) {
  if (name == "scalar") {
    *backend = RasterBackend::kScalar;
  } else if (name == "fixed") {
    *backend = RasterBackend::kFixedPoint;
  } else if (name == "simd") {
    *backend = RasterBackend::kSimd;
  } else if (name == "float-simd") {
    *backend = RasterBackend::kFloatSimd;
  } else {
    return false;
  }
  return true;
}

const char* RasterBackendName(RasterBackend backend) {
  switch (backend) {
    case RasterBackend::kScalar: return "scalar";
    case RasterBackend::kFixedPoint: return "fixed";
    case RasterBackend::kSimd: return "simd";
    case RasterBackend::kFloatSimd: return "float-simd";
  }
  return "unknown";
}

}  // namespace mcpose

#include <cmath>
#include <sstream>

#include "mcpose/options.h"

#include "render/raster_fixed.h"

namespace mcpose {

namespace {

bool Fail(std::string* error, const std::string& message) {
  if (error) *error = message;
  return false;
}

}  // namespace

bool EstimatorOptions::IsValid(std::string* error) const {
  auto finite_positive = [](double v) { return std::isfinite(v) && v > 0; };
  if (samples < 1) return Fail(error, "samples must be >= 1, got " + std::to_string(samples));
  if (max_iterations < 1)
    return Fail(error, "max_iterations must be >= 1, got " + std::to_string(max_iterations));
  if (!std::isfinite(tau)) return Fail(error, "tau must be finite");
  if (!(init_depth_quantile >= 0 && init_depth_quantile <= 1))
    return Fail(error, "init_depth_quantile must lie in [0, 1]");
  if (!(std::isfinite(init_sigma_t_m) && init_sigma_t_m >= 0))
    return Fail(error, "init_sigma_t_m must be finite and >= 0");
  if (!finite_positive(eps_m)) return Fail(error, "eps_m must be finite and > 0");
  for (double w : {weight_a, weight_b, weight_c})
    if (!(std::isfinite(w) && w >= 0)) return Fail(error, "weights a, b, c must be finite and >= 0");
  if (std::fabs(weight_a + weight_b + weight_c - 1.0) > 1e-6) {
    std::ostringstream os;
    os << "weights must sum to 1 (a + b + c = " << weight_a + weight_b + weight_c << ")";
    return Fail(error, os.str());
  }
  if (!(keep_top_fraction > 0 && keep_top_fraction <= 1))
    return Fail(error, "keep_top_fraction must lie in (0, 1]");
  if (cdf_table_size < 1) return Fail(error, "cdf_table_size must be >= 1");
  for (double s : {sigma_t_m, sigma_r_rad, sigma_t_min_m, sigma_r_min_rad})
    if (!(std::isfinite(s) && s >= 0)) return Fail(error, "diffusion sigmas must be finite and >= 0");
  if (!(anneal > 0 && anneal <= 1)) return Fail(error, "anneal must lie in (0, 1]");
  if (!(flip_rate >= 0 && flip_rate <= 1)) return Fail(error, "flip_rate must lie in [0, 1]");
  if (!(std::isfinite(lod_error_px) && lod_error_px >= 0))
    return Fail(error, "lod_error_px must be finite and >= 0 (0 = full mesh)");
  if (pixel_stride < 1 || pixel_stride > 16)
    return Fail(error, "pixel_stride must lie in [1, 16], got " + std::to_string(pixel_stride));
  if (max_grid_pixels < 0) return Fail(error, "max_grid_pixels must be >= 0 (0 = no budget)");
  if (threads < 0) return Fail(error, "threads must be >= 0 (0 = all hardware threads)");
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

std::string SimdTargets() { return render::SimdTargetsAvailable(); }
std::string ActiveSimdTarget() { return render::DispatchedSimdTarget(); }
bool LimitSimdTarget(const std::string& name) { return render::LimitSimdTargets(name); }

}  // namespace mcpose

#include "mcpose/options.h"

#include <cmath>
#include <functional>
#include <string>

#include <gtest/gtest.h>

#include "mcpose/estimator.h"

namespace mcpose {
namespace {

TEST(EstimatorOptions, DefaultsAreValidAndMatchThePaper) {
  EstimatorOptions o;
  std::string error;
  EXPECT_TRUE(o.IsValid(&error)) << error;
  EXPECT_EQ(o.samples, 620);
  EXPECT_EQ(o.max_iterations, 50);
  EXPECT_NEAR(o.weight.a + o.weight.b + o.weight.c, 1.0, 1e-12);
}

TEST(EstimatorOptions, EachInvalidFieldIsNamed) {
  const std::pair<std::function<void(EstimatorOptions&)>, std::string> cases[] = {
      {[](EstimatorOptions& o) { o.samples = 0; }, "samples"},
      {[](EstimatorOptions& o) { o.max_iterations = 0; }, "max_iterations"},
      {[](EstimatorOptions& o) { o.weight.eps_m = 0; }, "eps_m"},
      {[](EstimatorOptions& o) { o.weight.eps_m = NAN; }, "eps_m"},
      {[](EstimatorOptions& o) { o.weight.a = 0.9; }, "sum to 1"},
      {[](EstimatorOptions& o) { o.weight.box_fit = 1.5; }, "weight.box_fit"},
      {[](EstimatorOptions& o) { o.weight.box_fit = NAN; }, "weight.box_fit"},
      {[](EstimatorOptions& o) { o.weight.c = -0.1, o.weight.a = 0.65; }, "weight.c"},
      {[](EstimatorOptions& o) { o.resample.keep_top_fraction = 0; }, "keep_top_fraction"},
      {[](EstimatorOptions& o) { o.engine.pixel_stride = 0; }, "pixel_stride"},
      {[](EstimatorOptions& o) { o.engine.pixel_stride = 17; }, "pixel_stride"},
      {[](EstimatorOptions& o) { o.engine.max_grid_pixels = -1; }, "max_grid_pixels"},
      {[](EstimatorOptions& o) { o.resample.cdf_table_size = 0; }, "cdf_table_size"},
      {[](EstimatorOptions& o) { o.diffusion.anneal = 1.5; }, "anneal"},
      {[](EstimatorOptions& o) { o.diffusion.flip_rate = -0.1; }, "flip_rate"},
      {[](EstimatorOptions& o) { o.diffusion.flip_rate = NAN; }, "flip_rate"},
      {[](EstimatorOptions& o) { o.diffusion.sigma_r_rad = -1; }, "sigma"},
      {[](EstimatorOptions& o) { o.engine.lod_error_px = -1; }, "lod_error_px"},
      // Features that would have no effect name the fields involved.
      {[](EstimatorOptions& o) { o.engine.lod_error_px = 0; }, "engine.lod_unbiased"},
      {[](EstimatorOptions& o) { o.engine.lod_error_px = 0, o.engine.lod_unbiased = false; }, "engine.cluster_culling"},
      {[](EstimatorOptions& o) { o.engine.backend = RasterBackend::kScalar; }, "engine.cluster_culling"},
      {[](EstimatorOptions& o) { o.engine.backend = RasterBackend::kFloatSimd, o.engine.cluster_culling = false; },
       "engine.batched_setup"},
      {[](EstimatorOptions& o) { o.init.depth_quantile = 2; }, "init.depth_quantile"},
      {[](EstimatorOptions& o) { o.init.front_quantile = -0.1; }, "init.front_quantile"},
      {[](EstimatorOptions& o) { o.init.front_share = NAN; }, "init.front_share"},
      {[](EstimatorOptions& o) { o.init.rest_spread = 1.5; }, "init.rest_spread"},
      {[](EstimatorOptions& o) { o.init.wide = 0; }, "init.wide"},
      {[](EstimatorOptions& o) { o.init.wide = limits::kMaxInitWide + 1; }, "init.wide"},
      {[](EstimatorOptions& o) { o.samples = limits::kMaxSamples / 2, o.init.wide = 4; }, "samples * init.wide"},
      {[](EstimatorOptions& o) { o.resample.elite_share = -0.1; }, "resample.elite_share"},
      {[](EstimatorOptions& o) { o.resample.elite_share = 0.3; }, "resample.elite_share (0.3) must not exceed"},
      {[](EstimatorOptions& o) { o.appearance.twin_depth_margin = -0.01; }, "appearance.twin_depth_margin"},
      {[](EstimatorOptions& o) { o.appearance.hue_first_levels = -1; }, "appearance.hue_first_levels"},
      {[](EstimatorOptions& o) { o.appearance.hue_first_levels = NAN; }, "appearance.hue_first_levels"},
      {[](EstimatorOptions& o) { o.appearance.hue_first_levels = 256; }, "appearance.hue_first_levels"},
      {[](EstimatorOptions& o) {
         o.appearance.hue_first_levels = 8;
         o.appearance.space = AppearanceOptions::Space::kChroma;
       },
       "appearance.hue_first_levels needs appearance.space intensity-hue, not chroma"},
      {[](EstimatorOptions& o) { o.refine.accept_eps_m = -0.001; }, "refine.accept_eps_m"},
      {[](EstimatorOptions& o) { o.refine.accept_eps_m = NAN; }, "refine.accept_eps_m"},
      {[](EstimatorOptions& o) { o.engine.threads = -1; }, "threads"},
      {[](EstimatorOptions& o) { o.tau = INFINITY; }, "tau"},
      // Past the practical limits (include/mcpose/options.h, namespace limits).
      {[](EstimatorOptions& o) { o.samples = limits::kMaxSamples + 1; }, "samples"},
      {[](EstimatorOptions& o) { o.max_iterations = 1'000'000'000; }, "max_iterations"},
      {[](EstimatorOptions& o) { o.resample.cdf_table_size = 2'000'000'000; }, "cdf_table_size"},
      {[](EstimatorOptions& o) { o.engine.threads = 10'000; }, "threads"},
      {[](EstimatorOptions& o) { o.init.sigma_t_m = 1e30; }, "init.sigma_t_m"},
      {[](EstimatorOptions& o) { o.diffusion.sigma_t_m = 1e30; }, "sigma"},
      {[](EstimatorOptions& o) { o.diffusion.sigma_r_rad = 100; }, "sigma"},
      {[](EstimatorOptions& o) { o.refine.max_iterations = 1'000'000'000; }, "refine.max_iterations"},
      {[](EstimatorOptions& o) { o.appearance.twin_refine_iterations = 1'000'000'000; }, "twin_refine_iterations"},
  };
  for (const auto& [mutate, field] : cases) {
    EstimatorOptions o;
    mutate(o);
    std::string error;
    EXPECT_FALSE(o.IsValid(&error)) << field;
    EXPECT_NE(error.find(field), std::string::npos) << error;
    auto est = Estimator::Create(o);
    EXPECT_FALSE(est.ok());
    EXPECT_NE(est.status().message().find(field), std::string::npos);
  }
}

// The reference engine and any backend after DropUnusableFeatures are valid, and dropping keeps
// every feature the backend can use.
TEST(EngineOptions, ReferenceAndDroppedFeaturesAreValid) {
  EstimatorOptions o;
  o.engine = EngineOptions::Reference();
  std::string error;
  EXPECT_TRUE(o.IsValid(&error)) << error;
  EXPECT_EQ(o.engine.backend, RasterBackend::kScalar);
  EXPECT_EQ(o.engine.pixel_stride, 1);
  EXPECT_EQ(o.engine.lod_error_px, 0);
  for (RasterBackend b :
       {RasterBackend::kScalar, RasterBackend::kFixedPoint, RasterBackend::kSimd, RasterBackend::kFloatSimd,
        RasterBackend::kHardware}) {
    for (double lod : {0.0, 2.0}) {
      EstimatorOptions e;
      e.engine.backend = b;
      e.engine.lod_error_px = lod;
      e.engine.DropUnusableFeatures();
      EXPECT_TRUE(e.IsValid(&error)) << RasterBackendName(b) << " lod " << lod << ": " << error;
      EXPECT_EQ(e.engine.batched_setup, IsFixedPoint(b));
      EXPECT_EQ(e.engine.cluster_culling, IsFixedPoint(b) && lod > 0);
      EXPECT_EQ(e.engine.lod_unbiased, lod > 0);
    }
  }
}

TEST(EstimatorOptions, HardwareBackendCountsOneDimensionalInliersOnly) {
  for (RasterBackend b : {RasterBackend::kHardware, RasterBackend::kRtl}) {
    if (b == RasterBackend::kRtl && !RtlBackendAvailable()) continue;
    EstimatorOptions o;
    o.engine.backend = b;
    o.engine.DropUnusableFeatures();
    std::string error;
    EXPECT_TRUE(o.IsValid(&error)) << error;
    o.weight.inlier = InlierMode::k3D;
    EXPECT_FALSE(o.IsValid(&error));
    EXPECT_NE(error.find(std::string("engine.backend ") + RasterBackendName(b)), std::string::npos) << error;
  }
}

TEST(EstimatorOptions, RtlBackendOnlyWhereBuiltWithVerilator) {
  EstimatorOptions o;
  o.engine.backend = RasterBackend::kRtl;
  o.engine.DropUnusableFeatures();
  std::string error;
  EXPECT_EQ(o.IsValid(&error), RtlBackendAvailable()) << error;
  if (!RtlBackendAvailable()) {
    EXPECT_NE(error.find("Verilator"), std::string::npos) << error;
  }
}

TEST(EstimatorOptions, BackendNamesRoundTrip) {
  for (RasterBackend b :
       {RasterBackend::kScalar, RasterBackend::kFixedPoint, RasterBackend::kSimd, RasterBackend::kFloatSimd,
        RasterBackend::kHardware, RasterBackend::kRtl}) {
    RasterBackend parsed;
    ASSERT_TRUE(ParseRasterBackend(RasterBackendName(b), &parsed));
    EXPECT_EQ(parsed, b);
  }
  RasterBackend parsed;
  EXPECT_FALSE(ParseRasterBackend("gpu", &parsed));
}

}  // namespace
}  // namespace mcpose

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
  EXPECT_NEAR(o.weight_a + o.weight_b + o.weight_c, 1.0, 1e-12);
}

TEST(EstimatorOptions, EachInvalidFieldIsNamed) {
  const std::pair<std::function<void(EstimatorOptions&)>, std::string> cases[] = {
      {[](EstimatorOptions& o) { o.samples = 0; }, "samples"},
      {[](EstimatorOptions& o) { o.max_iterations = 0; }, "max_iterations"},
      {[](EstimatorOptions& o) { o.eps_m = 0; }, "eps_m"},
      {[](EstimatorOptions& o) { o.eps_m = NAN; }, "eps_m"},
      {[](EstimatorOptions& o) { o.weight_a = 0.9; }, "sum to 1"},
      {[](EstimatorOptions& o) { o.weight_c = -0.1, o.weight_a = 0.65; }, "weights"},
      {[](EstimatorOptions& o) { o.keep_top_fraction = 0; }, "keep_top_fraction"},
      {[](EstimatorOptions& o) { o.pixel_stride = 0; }, "pixel_stride"},
      {[](EstimatorOptions& o) { o.pixel_stride = 17; }, "pixel_stride"},
      {[](EstimatorOptions& o) { o.max_grid_pixels = -1; }, "max_grid_pixels"},
      {[](EstimatorOptions& o) { o.cdf_table_size = 0; }, "cdf_table_size"},
      {[](EstimatorOptions& o) { o.anneal = 1.5; }, "anneal"},
      {[](EstimatorOptions& o) { o.flip_rate = -0.1; }, "flip_rate"},
      {[](EstimatorOptions& o) { o.flip_rate = NAN; }, "flip_rate"},
      {[](EstimatorOptions& o) { o.sigma_r_rad = -1; }, "sigma"},
      {[](EstimatorOptions& o) { o.init_depth_quantile = 2; }, "init_depth_quantile"},
      {[](EstimatorOptions& o) { o.threads = -1; }, "threads"},
      {[](EstimatorOptions& o) { o.tau = INFINITY; }, "tau"},
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

TEST(EstimatorOptions, BackendNamesRoundTrip) {
  for (RasterBackend b :
       {RasterBackend::kScalar, RasterBackend::kFixedPoint, RasterBackend::kSimd, RasterBackend::kFloatSimd}) {
    RasterBackend parsed;
    ASSERT_TRUE(ParseRasterBackend(RasterBackendName(b), &parsed));
    EXPECT_EQ(parsed, b);
  }
  RasterBackend parsed;
  EXPECT_FALSE(ParseRasterBackend("gpu", &parsed));
}

}  // namespace
}  // namespace mcpose

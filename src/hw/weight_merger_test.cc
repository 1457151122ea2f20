// The weight merger's Q16 weight against the float weight the estimator uses (score::Weight's
// formula), on random counts: each of its three floors loses less than 2^-16, the rounding of
// each coefficient less than 2^-17 times its ratio.
#include "hw/weight_merger.h"

#include <gtest/gtest.h>

#include "core/rng.h"

namespace mcpose::hw {
namespace {

double FloatWeight(const Counts& n, int32_t observed, double a, double b, double c, double score, bool occlusion_aware) {
  const int32_t rendered = occlusion_aware ? n.rendered - n.occluded : n.rendered;
  return a * (observed > 0 ? static_cast<double>(n.inliers) / observed : 0.0) +
         b * (rendered > 0 ? static_cast<double>(n.inliers) / rendered : 0.0) + c * score;
}

TEST(HwWeightMerger, WithinFiveUnitsOfTheFloatWeight) {
  Rng rng(5, 2);
  for (int trial = 0; trial < 20000; ++trial) {
    const auto observed = static_cast<int32_t>(rng.Uniform(0, 8192));
    Counts n;
    n.rendered = static_cast<int32_t>(rng.Uniform(0, 8192));
    n.inliers = static_cast<int32_t>(rng.Uniform(0, std::min(observed, n.rendered)));
    n.occluded = static_cast<int32_t>(rng.Uniform(0, n.rendered - n.inliers));
    const double a = rng.Uniform(0, 1), b = rng.Uniform(0, 1 - a), c = 1 - a - b, score = rng.Uniform(0, 1);
    const bool occlusion_aware = trial % 2 == 0;
    const WeightCoefficients w = QuantizeWeight(a, b, c, score, occlusion_aware);
    const double got = MergedWeight(n, observed, w) / 65536.0;
    const double want = FloatWeight(n, observed, a, b, c, score, occlusion_aware);
    ASSERT_NEAR(got, want, 5.0 / 65536) << "trial " << trial;
  }
}

TEST(HwWeightMerger, ZeroDenominatorsGiveZeroTerms) {
  const WeightCoefficients w = QuantizeWeight(0.55, 0.15, 0.30, 0.5, true);
  EXPECT_EQ(MergedWeight({0, 0, 0}, 0, w), (w.c * w.score) >> 16);
  // Every rendered pixel hidden: N_r - occluded = 0, the precision term is 0.
  EXPECT_EQ(MergedWeight({0, 10, 10}, 100, w), (w.c * w.score) >> 16);
  // The whole box an inlier, every rendered pixel one: a + b + c s.
  EXPECT_EQ(MergedWeight({100, 100, 0}, 100, w), w.a + w.b + ((w.c * w.score) >> 16));
}

}  // namespace
}  // namespace mcpose::hw

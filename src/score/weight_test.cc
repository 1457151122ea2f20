#include "score/weight.h"

#include <gtest/gtest.h>

namespace mcpose::score {
namespace {

TEST(Weight, Formula) {
  InlierCounts c{50, 100, 200};
  EXPECT_DOUBLE_EQ(Weight(c, 0.8, 0.5, 0.3, 0.2), 0.5 * 0.25 + 0.3 * 0.5 + 0.2 * 0.8);
  EXPECT_DOUBLE_EQ(Weight(InlierCounts{0, 0, 0}, 0.5, 0.4, 0.4, 0.2), 0.1);
  // Occlusion-aware: 40 of the 100 rendered pixels are hidden, precision = 50 / 60.
  const InlierCounts occ{50, 100, 200, 40};
  EXPECT_DOUBLE_EQ(Weight(occ, 0.8, 0.5, 0.3, 0.2), 0.5 * 0.25 + 0.3 * 0.5 + 0.2 * 0.8);
  EXPECT_DOUBLE_EQ(Weight(occ, 0.8, 0.5, 0.3, 0.2, true), 0.5 * 0.25 + 0.3 * 50.0 / 60.0 + 0.2 * 0.8);
  // The options overload is the same formula.
  WeightOptions w;
  w.a = 0.5, w.b = 0.3, w.c = 0.2, w.occlusion_aware = true;
  EXPECT_EQ(Weight(occ, 0.8, w), Weight(occ, 0.8, 0.5, 0.3, 0.2, true));
}

// The colour agreement counts as far as the depth agrees: A' = 0.5 + (A - 0.5) N / N_r, whether
// the rest of the rendered object is hidden (occluded) or floats in front of what is observed.
TEST(Weight, ColourAgreementIsDrawnToNeutralByTheShareOfDepthThatDisagrees) {
  InlierCounts c{60, 100, 200, 30};
  // 60 inliers whose model and observed red rise together: A = 1 on the one varying channel.
  c.colour.n = 60;
  for (int i = 0; i < 60; ++i) {
    const int64_t v = 40 + i;
    c.colour.m[0] += v, c.colour.o[0] += v, c.colour.mm[0] += v * v, c.colour.oo[0] += v * v, c.colour.mo[0] += v * v;
  }
  ASSERT_DOUBLE_EQ(ColourAgreement(c.colour, 20), 1.0);
  EXPECT_DOUBLE_EQ(VisibleColourAgreement(c, 20), 0.5 + 0.5 * 0.6);
  c.occluded = 0;  // the 40 others in front of the observed surface instead: the same
  EXPECT_DOUBLE_EQ(VisibleColourAgreement(c, 20), 0.5 + 0.5 * 0.6);
  EXPECT_DOUBLE_EQ(VisibleColourAgreement(InlierCounts{}, 20), kNeutralAgreement);
  AppearanceOptions a;
  a.weight = 0.3;
  a.trust_pixels = 0;
  WeightOptions w;
  EXPECT_DOUBLE_EQ(WeightWithColour(c, 0.8, w, a), 0.7 * Weight(c, 0.8, w) + 0.3 * 0.8);
  // Trusted by its pixel count: 60 pixels against trust_pixels 30 keep two thirds of the pull.
  a.trust_pixels = 30;
  EXPECT_DOUBLE_EQ(VisibleColourAgreement(c, a), 0.5 + 0.5 * 0.6 * 60.0 / 90.0);
  EXPECT_DOUBLE_EQ(WeightWithColour(c, 0.8, w, a), 0.7 * Weight(c, 0.8, w) + 0.3 * (0.5 + 0.3 * 60.0 / 90.0));
}

}  // namespace
}  // namespace mcpose::score

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

}  // namespace
}  // namespace mcpose::score

// Twin margins on a synthetic scene: a box whose six faces have six colours, seen so that its
// 180-degree turns are depth twins. With colour the truth outweighs every wrong turn; depth
// alone cannot tell them apart; from a wrong turn the candidates reach back to the truth.
#include "mcpose/analysis/twin_margin.h"

#include <gtest/gtest.h>

#include <cmath>

#include "mcpose/eval.h"
#include "synthetic_mesh.h"
#include "synthetic_scene.h"

namespace mcpose::analysis {
namespace {

const Eigen::Vector3f kLo(-0.06f, -0.04f, -0.025f), kHi(0.06f, 0.04f, 0.025f);
const Rgba8 kColours[6] = {{220, 40, 40, 255},  {40, 200, 40, 255},  {40, 40, 220, 255},
                           {220, 220, 40, 255}, {40, 200, 220, 255}, {200, 40, 200, 255}};

struct Scene {
  Mesh mesh;
  SE3 T_gt{ExpSO3(Eigen::Vector3d(0.5, -0.4, 0.3)), Eigen::Vector3d(0.0, 0.01, 0.6)};
  testing::SyntheticFrame frame;
  Detection box;
  std::vector<Eigen::Vector3f> points;
};

Scene MakeScene() {
  Scene s;
  s.mesh = testing::LatticeBox(kLo, kHi, 8, [](int f, const Eigen::Vector3f&) { return kColours[f]; });
  s.frame = testing::RenderFrame(
      s.mesh, s.T_gt,
      [](const Eigen::Vector3f& p) {
        int face = 0;
        float d = INFINITY;
        for (int f = 0; f < 6; ++f) {
          const float e = std::fabs(p[f / 2] - (f % 2 ? kHi[f / 2] : kLo[f / 2]));
          if (e < d) d = e, face = f;
        }
        return kColours[face];
      },
      5);
  EXPECT_GT(MaskBox(s.frame.visible, &s.box), 0);
  s.box.score = 1;
  s.points = s.mesh.vertices_m;
  return s;
}

EstimatorOptions Options(bool colour) {
  EstimatorOptions o;
  o.engine.threads = 2;
  o.appearance.enabled = colour;
  return o;
}

TEST(TwinMargin, ColourDecidesWhereDepthCannot) {
  const Scene s = MakeScene();
  TwinMarginOptions m;
  {
    Scorer context(Options(true));
    auto r = MeasureTwinMargin(context, s.frame.K, s.frame.depth, &s.frame.colour, s.mesh, s.box, s.T_gt, s.points,
                               false, m);
    ASSERT_TRUE(r.ok()) << r.status().ToString();
    EXPECT_TRUE(r->colour);
    EXPECT_EQ(r->candidates, 24);
    EXPECT_GT(r->wrong, 0);
    EXPECT_GT(r->margin, 0.02);
    EXPECT_GT(r->colour_margin, 0.1);
    EXPECT_GT(r->colour_pixels, 100);
    // Depth alone: the flips fit the depth as well as the truth.
    EXPECT_LT(std::fabs(r->depth_margin), 0.02);
  }
  {
    Scorer context(Options(false));
    auto r = MeasureTwinMargin(context, s.frame.K, s.frame.depth, &s.frame.colour, s.mesh, s.box, s.T_gt, s.points,
                               false, m);
    ASSERT_TRUE(r.ok());
    EXPECT_FALSE(r->colour);
    EXPECT_LT(r->margin, 0.02);
  }
  m.right_m = 0.05, m.wrong_m = 0.01;
  Scorer context(Options(true));
  EXPECT_FALSE(
      MeasureTwinMargin(context, s.frame.K, s.frame.depth, &s.frame.colour, s.mesh, s.box, s.T_gt, s.points, false, m)
          .ok());
}

TEST(TwinMargin, FromAWrongTurnTheCandidatesReachTheTruth) {
  const Scene s = MakeScene();
  Scorer context(Options(true));
  // The truth turned 180 degrees about the model's x axis through the box centre (the centre is
  // the origin here): a depth twin.
  const SE3 flipped(s.T_gt.R * Eigen::Vector3d(1, -1, -1).asDiagonal(), s.T_gt.t);
  auto r = MeasureTwinReach(context, s.frame.K, s.frame.depth, &s.frame.colour, s.mesh, s.box, flipped, s.T_gt,
                            s.points, false);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_LT(r->nearest_m, 0.003);
  EXPECT_GT(r->nearest_weight, r->estimate_weight + 0.02);
  EXPECT_LT(r->best_m, 0.003);
}

}  // namespace
}  // namespace mcpose::analysis

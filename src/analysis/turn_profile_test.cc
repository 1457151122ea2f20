// Turn profiles: the statistics on hand-made profiles, and the profile of a synthetic cuboid,
// whose half turn about an axis through its centre gives the same depth and a quarter turn does not.
#include "mcpose/analysis/turn_profile.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "core/rng.h"
#include "render/raster.h"
#include "synthetic_mesh.h"

namespace mcpose::analysis {
namespace {

TEST(TurnProfile, StatisticsOfHandMadeProfiles) {
  // 72 turns of 5 degrees: flat at 0.7 with +-e alternating on top.
  const double e = 0.001;
  std::vector<double> w(72);
  for (size_t k = 0; k < w.size(); ++k) w[k] = 0.7 + (k % 2 ? -e : e);
  TurnProfileStats s = SummarizeTurnProfile(w, 5, 10);
  EXPECT_NEAR(s.jitter, 4 * e / std::sqrt(6.0), 1e-12);  // each second difference is +-4e
  EXPECT_NEAR(s.range, 2 * e / 7, 1e-12);                // a 7-step mean leaves +-e/7
  EXPECT_NEAR(s.truth, 0.7 + e, 1e-12);                  // the best of turns 0, +-5, +-10
  EXPECT_EQ(s.beaten, 0.0);                               // no far turn beats 0.7 + e

  // A smooth bump at the truth and two far turns above it: no jitter from the flat part.
  std::vector<double> v(72, 0.5);
  v[0] = 1.0;
  v[30] = v[40] = 1.5;
  s = SummarizeTurnProfile(v, 5, 10);
  EXPECT_EQ(s.truth, 1.0);
  EXPECT_NEAR(s.beaten, 2.0 / 67, 1e-12);  // turns 0, 5, 10, 350, 355 are near: 67 far
  std::vector<double> flat(72, 0.8);
  s = SummarizeTurnProfile(flat, 5, 10);
  EXPECT_EQ(s.jitter, 0.0);
  EXPECT_EQ(s.range, 0.0);
  EXPECT_EQ(s.beaten, 0.0);
}

TEST(TurnProfile, OptionsAreChecked) {
  TurnProfileOptions o;
  std::string error;
  EXPECT_TRUE(o.IsValid(&error)) << error;
  o.step_deg = 7;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("divide 360"), std::string::npos);
  o = TurnProfileOptions{};
  o.axis = 3;
  EXPECT_FALSE(o.IsValid(&error));
  o = TurnProfileOptions{};
  o.step_deg = NAN;
  EXPECT_FALSE(o.IsValid(&error));
}

constexpr int kW = 320, kH = 240;

struct Scene {
  Intrinsics K{600, 600, 160, 120, kW, kH};
  Mesh mesh;
  SE3 T_gt{ExpSO3(Eigen::Vector3d(0.4, -0.3, 0.5)), Eigen::Vector3d(-0.02, 0.01, 0.7)};
  DepthImage depth;
  Detection box;
};

// An off-centre cuboid with three different sides seen at T_gt in front of random depths.
Scene Cuboid() {
  Scene s;
  testing::AddBox(&s.mesh, {-0.04f, -0.02f, -0.01f}, {0.08f, 0.05f, 0.02f});
  render::RasterParams p;
  p.fx = p.fy = 600, p.cx = 160, p.cy = 120;
  p.box = {0, 0, kW, kH};
  std::vector<render::ScreenVertex> sv(s.mesh.vertices_m.size());
  render::ProjectVertices(s.mesh.vertices_m, s.T_gt.R.cast<float>(), s.T_gt.t.cast<float>(), p, sv);
  s.depth.width = kW, s.depth.height = kH;
  s.depth.depth_m.assign(kW * kH, INFINITY);
  render::RasterizeDepthReference(sv, s.mesh.triangles, p, s.depth.depth_m.data(), nullptr);
  int x0 = kW, y0 = kH, x1 = 0, y1 = 0;  // the box: the cuboid's pixels and 4 around
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      if (std::isfinite(s.depth.depth_m[static_cast<size_t>(y) * kW + x]))
        x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x + 1), y1 = std::max(y1, y + 1);
  s.box.obj_id = 1, s.box.score = 0.9;
  s.box.x = x0 - 4, s.box.y = y0 - 4, s.box.w = x1 - x0 + 8, s.box.h = y1 - y0 + 8;
  Rng rng(5, 6);
  for (float& z : s.depth.depth_m)
    if (std::isinf(z)) z = static_cast<float>(rng.Uniform(0.9, 1.5));
  return s;
}

EstimatorOptions Reference() {
  EstimatorOptions o;
  o.engine = EngineOptions::Reference();
  o.engine.backend = RasterBackend::kFloatSimd;
  o.engine.threads = 2;
  return o;
}

TEST(TurnProfile, CuboidHalfTurnScoresAsTheTruthAndAQuarterTurnLower) {
  const Scene s = Cuboid();
  for (int axis = 0; axis < 3; ++axis) {
    TurnProfileOptions turn;
    turn.step_deg = 10, turn.axis = axis;
    auto p = ProfileTurns(s.K, s.depth, nullptr, s.mesh, s.box, s.T_gt, Reference(), turn);
    ASSERT_TRUE(p.ok()) << p.status().ToString();
    ASSERT_EQ(p->weight.size(), 36u);
    EXPECT_EQ(p->axis, axis);
    EXPECT_EQ(p->angle_deg[9], 90.0);
    EXPECT_EQ(p->triangles, 12);
    EXPECT_EQ(p->stride, 1);
    // Every rendered pixel of the truth is an inlier (N = N_r): w >= b + c * score.
    const EstimatorOptions o = Reference();
    EXPECT_GT(p->weight[0], o.weight.b + o.weight.c * 0.9 + 0.1) << axis;
    EXPECT_EQ(p->weight[0], *std::max_element(p->weight.begin(), p->weight.end())) << axis;
    EXPECT_NEAR(p->weight[18], p->weight[0], 0.01) << axis;  // the half turn: the same cuboid
    EXPECT_LT(p->weight[9], p->weight[0] - 0.05) << axis;    // a quarter turn: another shape
    EXPECT_EQ(p->stats.truth, std::max({p->weight[0], p->weight[1], p->weight[35]}));
    // Only turns near the half turn can beat the truth.
    EXPECT_LE(p->stats.beaten, 3.0 / 31) << axis;
  }
}

TEST(TurnProfile, TheDefaultsScoreAtTheirStride) {
  const Scene s = Cuboid();
  EstimatorOptions o;  // stride 2, LOD on (the 12-triangle cuboid has no coarser level)
  o.engine.threads = 1;
  auto p = ProfileTurns(s.K, s.depth, nullptr, s.mesh, s.box, s.T_gt, o, TurnProfileOptions{});
  ASSERT_TRUE(p.ok()) << p.status().ToString();
  EXPECT_EQ(p->stride, 2) << s.box.w << "x" << s.box.h;
  EXPECT_EQ(p->weight.size(), 72u);
  EXPECT_EQ(p->triangles, 12);
  o.engine.threads = 2;  // the raster cores give the same counts at any thread count
  auto q = ProfileTurns(s.K, s.depth, nullptr, s.mesh, s.box, s.T_gt, o, TurnProfileOptions{});
  ASSERT_TRUE(q.ok());
  EXPECT_EQ(p->weight, q->weight);
}

TEST(TurnProfile, BadInputIsNamed) {
  const Scene s = Cuboid();
  Detection outside = s.box;
  outside.x = 5000;
  auto p = ProfileTurns(s.K, s.depth, nullptr, s.mesh, outside, s.T_gt, Reference(), TurnProfileOptions{});
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.status().message().find("outside the"), std::string::npos);
  TurnProfileOptions bad;
  bad.step_deg = 0;
  p = ProfileTurns(s.K, s.depth, nullptr, s.mesh, s.box, s.T_gt, Reference(), bad);
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.status().message().find("step_deg"), std::string::npos);
  p = ProfileTurns(s.K, s.depth, nullptr, Mesh{}, s.box, s.T_gt, Reference(), TurnProfileOptions{});
  EXPECT_FALSE(p.ok());
}

}  // namespace
}  // namespace mcpose::analysis

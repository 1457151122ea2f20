// Depth ambiguity on synthetic scenes: a cuboid with three different sides has exactly the
// four depth-identical poses of its symmetry group; an L of two blocks has one.
#include "mcpose/analysis/depth_ambiguity.h"
#include "analysis/ambiguity_instance.h"

#include <cmath>

#include <gtest/gtest.h>

#include "core/rng.h"
#include "synthetic_mesh.h"

namespace mcpose::analysis {
namespace {

constexpr int kW = 320, kH = 240;

struct Scene {
  Intrinsics K{600, 600, 160, 120, kW, kH};
  Mesh mesh;
  std::vector<Eigen::Vector3f> points;  // the mesh vertices
  SE3 T_gt{ExpSO3(Eigen::Vector3d(0.4, -0.3, 0.5)), Eigen::Vector3d(-0.02, 0.01, 0.7)};
  DepthImage depth;
  render::PixelRect box{0, 0, kW, kH};
};

// Observed depth: the object at T_gt in front of random depths in 0.9-1.5 m.
void Observe(Scene* s) {
  render::RasterParams p;
  p.fx = p.fy = 600, p.cx = 160, p.cy = 120;
  p.box = s->box;
  std::vector<render::ScreenVertex> sv(s->mesh.vertices_m.size());
  render::ProjectVertices(s->mesh.vertices_m, s->T_gt.R.cast<float>(), s->T_gt.t.cast<float>(), p, sv);
  s->depth.width = kW, s->depth.height = kH;
  s->depth.depth_m.assign(kW * kH, INFINITY);
  render::RasterizeDepthReference(sv, s->mesh.triangles, p, s->depth.depth_m.data(), nullptr);
  Rng rng(5, 6);
  for (float& z : s->depth.depth_m)
    if (std::isinf(z)) z = static_cast<float>(rng.Uniform(0.9, 1.5));
  s->points = s->mesh.vertices_m;
}

Scene Cuboid() {
  Scene s;
  // Off-centre on purpose: the turns are about the bounding-box centre, not the origin.
  testing::AddBox(&s.mesh, {-0.04f, -0.02f, -0.01f}, {0.08f, 0.05f, 0.02f});
  Observe(&s);
  return s;
}

TEST(DepthAmbiguity, CandidatesAreDistinctRotationsIdentityFirst) {
  for (double step : {90.0, 15.0}) {
    const auto c = CandidateRotations(step);
    ASSERT_FALSE(c.empty());
    EXPECT_TRUE(c[0].isApprox(Eigen::Matrix3d::Identity()));
    for (size_t i = 0; i < c.size(); ++i) {
      EXPECT_NEAR(c[i].determinant(), 1.0, 1e-9);
      EXPECT_TRUE((c[i].transpose() * c[i]).isApprox(Eigen::Matrix3d::Identity(), 1e-9));
      for (size_t j = 0; j < i; ++j) EXPECT_GT((c[i] - c[j]).norm(), 1e-6) << step << " " << i << " " << j;
    }
  }
  // Quarter turns about the three axes (10 distinct) composed with the half turns: 16 of the
  // cube's 24 rotations (the set is turns about one axis after a flip, not the whole group).
  EXPECT_EQ(CandidateRotations(90).size(), 16u);
}

TEST(DepthAmbiguity, CuboidHasFourEquivalentPoses) {
  const Scene s = Cuboid();
  AmbiguityOptions o;
  o.step_deg = 90;
  const InstanceAmbiguity add = AnalyzeInstance(s.K, s.depth, s.mesh, s.points, s.T_gt, s.box, false, o);
  EXPECT_EQ(add.candidates, 16);
  EXPECT_EQ(add.equivalent, 4);          // the identity and the three half turns
  EXPECT_EQ(add.equivalent_correct, 1);  // the half turns move the corners by > 4 cm
  EXPECT_DOUBLE_EQ(add.ceiling, 0.25);
  const InstanceAmbiguity adds = AnalyzeInstance(s.K, s.depth, s.mesh, s.points, s.T_gt, s.box, true, o);
  EXPECT_EQ(adds.equivalent, 4);
  EXPECT_DOUBLE_EQ(adds.ceiling, 1.0);  // ADD-S: the flips are the same surface
}

TEST(DepthAmbiguity, AsymmetricObjectHasOnlyItself) {
  Scene s;
  testing::AddBox(&s.mesh, {-0.05f, -0.03f, -0.02f}, {0.05f, 0.03f, 0.02f});
  testing::AddBox(&s.mesh, {0.02f, 0.03f, -0.02f}, {0.05f, 0.08f, 0.02f});
  Observe(&s);
  AmbiguityOptions o;
  o.step_deg = 30;
  const InstanceAmbiguity a = AnalyzeInstance(s.K, s.depth, s.mesh, s.points, s.T_gt, s.box, false, o);
  EXPECT_GT(a.candidates, 24);
  EXPECT_EQ(a.equivalent, 1);
  EXPECT_DOUBLE_EQ(a.ceiling, 1.0);
}

TEST(DepthAmbiguity, FullyOccludedObjectIsAmbiguous) {
  Scene s = Cuboid();
  for (float& z : s.depth.depth_m) z = 0.3f;  // a wall in front of everything
  AmbiguityOptions o;
  o.step_deg = 90;
  const InstanceAmbiguity a = AnalyzeInstance(s.K, s.depth, s.mesh, s.points, s.T_gt, s.box, false, o);
  EXPECT_EQ(a.equivalent, a.candidates);
  EXPECT_LT(a.ceiling, 0.5);
}

TEST(DepthAmbiguity, OptionsAreValidated) {
  std::string error;
  EXPECT_TRUE(AmbiguityOptions{}.IsValid(&error));
  AmbiguityOptions o;
  o.step_deg = 0;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("step_deg"), std::string::npos);
  o = AmbiguityOptions{};
  o.min_agreement = NAN;
  EXPECT_FALSE(o.IsValid(&error));
}

}  // namespace
}  // namespace mcpose::analysis

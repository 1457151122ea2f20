// Refinement floor on a synthetic scene: a cuboid whose observed depth is rendered at the truth
// comes back to the truth from a start 5 mm and 3 degrees away; where the depth was rendered at
// a pose 2 mm beside the truth (the truth misannotated), the alignment lands on the depth and
// the floor reports the 2 mm.
#include "analysis/refine_floor_instance.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "mcpose/eval.h"
#include "synthetic_mesh.h"
#include "synthetic_scene.h"

namespace mcpose::analysis {
namespace {

struct Scene {
  Mesh mesh;
  testing::SyntheticFrame frame;
  std::vector<Eigen::Vector3f> points;  // the mesh vertices
  SE3 T_gt{ExpSO3(Eigen::Vector3d(0.4, -0.3, 0.5)), Eigen::Vector3d(-0.02, 0.01, 0.7)};
  render::PixelRect box{0, 0, 320, 240};
};

// A cuboid with three different sides, its observed depth rendered at `T_depth` in front of
// random depths in 0.9-1.5 m.
Scene MakeScene(const SE3& T_depth) {
  Scene s;
  testing::AddBox(&s.mesh, {-0.04f, -0.02f, -0.01f}, {0.08f, 0.05f, 0.03f});
  s.frame = testing::RenderFrame(s.mesh, T_depth, [](const Eigen::Vector3f&) { return Rgba8{128, 128, 128, 255}; }, 6);
  s.points = s.mesh.vertices_m;
  return s;
}

TEST(RefineFloor, StartPoseLiesTheGivenDistanceAndTurnFromTheTruth) {
  RefineFloorOptions o;
  o.start_mm = 7, o.start_deg = 4;
  const SE3 T{ExpSO3(Eigen::Vector3d(0.1, 0.2, -0.3)), Eigen::Vector3d(0.1, -0.05, 0.9)};
  for (uint64_t i = 0; i < 20; ++i) {
    const SE3 s = StartPose(T, o, i);
    EXPECT_NEAR(1000 * (s.t - T.t).norm(), 7.0, 1e-9);
    EXPECT_NEAR(LogSO3(s.R * T.R.transpose()).norm() * 180 / std::numbers::pi, 4.0, 1e-6);
    EXPECT_FALSE(StartPose(T, o, i).t.isApprox(StartPose(T, o, i + 1).t)) << "each instance its own direction";
  }
  o.start_mm = 0, o.start_deg = 0;
  EXPECT_TRUE(StartPose(T, o, 3).t.isApprox(T.t));
  EXPECT_TRUE(StartPose(T, o, 3).R.isApprox(T.R));
}

TEST(RefineFloor, ReturnsToTheTruthWhereDepthAgreesWithIt) {
  const Scene s = MakeScene(SE3{ExpSO3(Eigen::Vector3d(0.4, -0.3, 0.5)), Eigen::Vector3d(-0.02, 0.01, 0.7)});
  RefineFloorOptions o;
  o.start_mm = 5, o.start_deg = 3;
  for (uint64_t i = 0; i < 5; ++i) {
    const InstanceFloor f = AnalyzeInstance(s.frame.K, s.frame.depth, s.mesh, s.points, s.T_gt, s.box, o, i);
    EXPECT_GT(f.adds_start_m, 0.003) << i;
    EXPECT_LT(f.adds_aligned_m, 0.0005) << i;
    EXPECT_GT(f.iterations, 0) << i;
  }
}

TEST(RefineFloor, MeasuresTheDisagreementOfTruthAndDepth) {
  // The depth shows the cuboid 2 mm to the right of the truth (across the viewing ray).
  const SE3 T_gt{ExpSO3(Eigen::Vector3d(0.4, -0.3, 0.5)), Eigen::Vector3d(-0.02, 0.01, 0.7)};
  const Eigen::Vector3d ray = T_gt.t.normalized();
  const Eigen::Vector3d side = ray.cross(Eigen::Vector3d::UnitY()).normalized();
  const Scene s = MakeScene(SE3{T_gt.R, T_gt.t + 0.002 * side});
  RefineFloorOptions o;  // from the truth itself
  const InstanceFloor f = AnalyzeInstance(s.frame.K, s.frame.depth, s.mesh, s.points, T_gt, s.box, o, 0);
  EXPECT_NEAR(f.adds_start_m, 0.0, 1e-12);
  EXPECT_NEAR(f.across_ray_mm, 2.0, 0.3);
  EXPECT_NEAR(f.along_ray_mm, 0.0, 0.3);
  EXPECT_NEAR(1000 * f.adds_aligned_m, 2.0, 0.4);
}

TEST(RefineFloor, OptionsAreChecked) {
  std::string error;
  EXPECT_TRUE(RefineFloorOptions{}.IsValid(&error)) << error;
  RefineFloorOptions o;
  o.start_mm = -1;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("start_mm"), std::string::npos);
  o = {};
  o.start_deg = NAN;
  EXPECT_FALSE(o.IsValid(&error));
  o = {};
  o.refine.tukey_m = 0;
  EXPECT_FALSE(o.IsValid(&error));
  o = {};
  o.box_margin = -0.1;
  EXPECT_FALSE(o.IsValid(&error));
}

}  // namespace
}  // namespace mcpose::analysis

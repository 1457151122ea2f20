#include "refine/align.h"

#include <cmath>

#include <gtest/gtest.h>

#include "core/rng.h"
#include "synthetic_mesh.h"
#include "synthetic_scene.h"

namespace mcpose::refine {
namespace {

// The blob at a pose in front of random background depths, and its tight box (a margin of
// 12 pixels).
struct Scene {
  Mesh mesh = testing::Blob();
  SE3 T_gt{ExpSO3(Eigen::Vector3d(0.4, -0.3, 0.5)), Eigen::Vector3d(-0.01, 0.01, 0.5)};
  testing::SyntheticFrame frame;
  render::PixelRect box;
};

Scene MakeScene() {
  Scene s;
  s.frame = testing::RenderFrame(s.mesh, s.T_gt, [](const Eigen::Vector3f&) { return Rgba8{128, 128, 128, 255}; }, 2);
  int x0 = 320, y0 = 240, x1 = 0, y1 = 0;
  for (int y = 0; y < 240; ++y)
    for (int x = 0; x < 320; ++x)
      if (s.frame.visible.values[y * 320 + x]) x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
  s.box = render::PixelRect{std::max(0, x0 - 12), std::max(0, y0 - 12), std::min(320, x1 + 13), std::min(240, y1 + 13)};
  return s;
}

// `T` moved by up to 1 cm and 5 degrees, a random direction each.
SE3 Perturb(const SE3& T, Rng& rng) {
  const Eigen::Vector3d axis = Eigen::Vector3d(rng.Normal(), rng.Normal(), rng.Normal()).normalized();
  const Eigen::Vector3d dir = Eigen::Vector3d(rng.Normal(), rng.Normal(), rng.Normal()).normalized();
  const double angle = rng.Uniform(0.5, 5.0) * M_PI / 180, shift = rng.Uniform(0.002, 0.01);
  return SE3(ExpSO3(axis * angle) * T.R, T.t + shift * dir);
}

TEST(Align, PerturbedPosesReturnWithinAMillimetreAndHalfADegree) {
  const Scene s = MakeScene();
  Rng rng(11, 11);
  for (int k = 0; k < 12; ++k) {
    const SE3 start = Perturb(s.T_gt, rng);
    const AlignResult r = AlignToDepth(s.frame.K, s.frame.depth, s.box, s.mesh, start, AlignOptions{});
    const double dt = (r.T_cam_obj.t - s.T_gt.t).norm(), dr = RotationAngle(r.T_cam_obj.R, s.T_gt.R) * 180 / M_PI;
    EXPECT_LT(dt, 0.001) << k;
    EXPECT_LT(dr, 0.5) << k;
    EXPECT_TRUE(r.moved);
    EXPECT_LT(r.rms_after_m, r.rms_before_m) << k;
  }
}

// A flat occluder 5 cm in front of the object covers 40 % of the box: its pixels lie in front
// of the model, so they are left out, and the alignment still converges.
TEST(Align, ConvergesWithFortyPercentOfTheBoxOccluded) {
  Scene s = MakeScene();
  const int cut = s.box.x0 + static_cast<int>(0.4 * s.box.width());
  for (int y = s.box.y0; y < s.box.y1; ++y)
    for (int x = s.box.x0; x < cut; ++x) s.frame.depth.depth_m[y * 320 + x] = static_cast<float>(s.T_gt.t.z() - 0.05);
  Rng rng(12, 12);
  for (int k = 0; k < 8; ++k) {
    const SE3 start = Perturb(s.T_gt, rng);
    const AlignResult r = AlignToDepth(s.frame.K, s.frame.depth, s.box, s.mesh, start, AlignOptions{});
    EXPECT_LT((r.T_cam_obj.t - s.T_gt.t).norm(), 0.0015) << k;
    EXPECT_LT(RotationAngle(r.T_cam_obj.R, s.T_gt.R) * 180 / M_PI, 1.0) << k;
  }
}

TEST(Align, NothingToAlignLeavesThePose) {
  const Scene s = MakeScene();
  DepthImage empty = s.frame.depth;
  std::fill(empty.depth_m.begin(), empty.depth_m.end(), 0.f);
  const AlignResult r = AlignToDepth(s.frame.K, empty, s.box, s.mesh, s.T_gt, AlignOptions{});
  EXPECT_FALSE(r.moved);
  EXPECT_EQ(r.T_cam_obj.t, s.T_gt.t);
  EXPECT_EQ(r.iterations, 0);
}

}  // namespace
}  // namespace mcpose::refine

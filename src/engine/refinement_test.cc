#include "engine/refinement.h"

#include <cmath>

#include <gtest/gtest.h>

#include "engine/context.h"
#include "synthetic_mesh.h"
#include "synthetic_scene.h"

namespace mcpose::engine {
namespace {

struct Scene {
  Mesh mesh = testing::Blob();
  SE3 T_gt{ExpSO3(Eigen::Vector3d(0.4, -0.3, 0.5)), Eigen::Vector3d(-0.01, 0.01, 0.5)};
  testing::SyntheticFrame frame;
  Detection box;
};

// The blob over random background; its colour a field over the model, so that a shifted pose
// shows other colours.
Scene MakeScene() {
  Scene s;
  for (const Eigen::Vector3f& v : s.mesh.vertices_m)
    s.mesh.appearance.vertex_colours.push_back({static_cast<uint8_t>(128 + 2000 * v.x()), static_cast<uint8_t>(128 + 2000 * v.y()),
                                                static_cast<uint8_t>(128 + 1500 * v.z()), 255});
  s.frame = testing::RenderFrame(
      s.mesh, s.T_gt,
      [](const Eigen::Vector3f& p) {
        return Rgba8{static_cast<uint8_t>(128 + 2000 * p.x()), static_cast<uint8_t>(128 + 2000 * p.y()),
                     static_cast<uint8_t>(128 + 1500 * p.z()), 255};
      },
      4);
  int x0 = 320, y0 = 240, x1 = 0, y1 = 0;
  for (int y = 0; y < 240; ++y)
    for (int x = 0; x < 320; ++x)
      if (s.frame.visible.values[y * 320 + x]) x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
  s.box = Detection{1, 1, 1, 0.9, x0 - 10.0, y0 - 10.0, x1 - x0 + 21.0, y1 - y0 + 21.0};
  return s;
}

std::unique_ptr<BoxScorer> FullScorer(Context& context, const Scene& s, const ColourImage* colour) {
  auto r = BoxScorer::Create(context, s.frame.K, s.frame.depth, s.mesh, std::span(&s.box, 1), colour, Resolution::kFull);
  EXPECT_TRUE(r.ok()) << r.status().ToString();
  return std::move(r).value();
}

TEST(Refinement, APerturbedPoseIsAlignedAndAccepted) {
  const Scene s = MakeScene();
  EstimatorOptions o;
  o.engine.threads = 1;
  Context context(o);
  auto full = FullScorer(context, s, nullptr);
  ObjectEstimate e;
  e.T_cam_obj = SE3(ExpSO3(Eigen::Vector3d(0.03, -0.05, 0.02)) * s.T_gt.R, s.T_gt.t + Eigen::Vector3d(0.004, -0.006, 0.005));
  const ObjectEstimate r = RefineEstimate(o.refine, *full, s.frame.depth, e);
  EXPECT_TRUE(r.refine.ran);
  EXPECT_TRUE(r.refine.accepted);
  EXPECT_GE(r.refine.weight_after, r.refine.weight_before);
  EXPECT_LT(r.refine.rms_after_m, r.refine.rms_before_m);
  EXPECT_LT((r.T_cam_obj.t - s.T_gt.t).norm(), 0.001);
  EXPECT_LT(RotationAngle(r.T_cam_obj.R, s.T_gt.R) * 180 / M_PI, 0.5);
}

// The colour image shifted 8 pixels against the depth: the pose whose colour fits best lies off
// the depth's best pose. Weighed mostly by colour, with the filter's centimetre as the inlier
// threshold (within which the shifted pose still has most of its depth), alignment to the depth
// would lower the weight of that pose, so it is rejected and the pose kept as it was.
TEST(Refinement, AnAlignmentThatLowersTheWeightIsRejected) {
  Scene s = MakeScene();
  ColourImage shifted = s.frame.colour;
  for (int y = 0; y < 240; ++y)
    for (int x = 0; x < 320; ++x)
      for (int c = 0; c < 4; ++c)
        shifted.rgba[4 * (y * 320 + x) + c] = s.frame.colour.rgba[4 * (y * 320 + std::max(0, x - 8)) + c];
  EstimatorOptions o;
  o.engine.threads = 1;
  o.appearance.weight = 0.9;
  // Colour's full say, of each pixel alone, intensity and hue together: the rejection is tested,
  // not the trust, smoothing or hue first.
  o.appearance.trust_pixels = 0;
  o.appearance.smooth_radius = 0;
  o.appearance.hue_first_levels = 0;
  o.refine.accept_eps_m = 0;
  Context context(o);
  auto full = FullScorer(context, s, &shifted);
  ASSERT_TRUE(full->uses_colour());
  // The colour's best pose: the truth moved 8 pixels to the right, at the object's depth.
  ObjectEstimate e;
  e.T_cam_obj = SE3(s.T_gt.R, s.T_gt.t + Eigen::Vector3d(8 * s.T_gt.t.z() / s.frame.K.fx, 0, 0));
  const ObjectEstimate r = RefineEstimate(o.refine, *full, s.frame.depth, e);
  EXPECT_TRUE(r.refine.ran);
  EXPECT_FALSE(r.refine.accepted);
  EXPECT_EQ(r.refine.weight_after, r.refine.weight_before);
  EXPECT_EQ(r.T_cam_obj.t, e.T_cam_obj.t);
  EXPECT_EQ(r.T_cam_obj.R, e.T_cam_obj.R);
}

// The pose is judged by the weight with its inliers counted within accept_eps_m; the scorer's
// own threshold is what it was afterwards. A start 3 mm behind the surface has every pixel
// within the filter's centimetre, but none within 2 mm: weighed at 2 mm, the aligned pose must
// gain, and the weight reported is the one at that threshold.
TEST(Refinement, IsJudgedAtItsOwnInlierThreshold) {
  const Scene s = MakeScene();
  EstimatorOptions o;
  o.engine.threads = 1;
  o.refine.accept_eps_m = 0.002;
  Context context(o);
  auto full = FullScorer(context, s, nullptr);
  ObjectEstimate e;
  e.T_cam_obj = SE3(s.T_gt.R, s.T_gt.t + 0.003 * s.T_gt.t.normalized());
  const ObjectEstimate r = RefineEstimate(o.refine, *full, s.frame.depth, e);
  EXPECT_FLOAT_EQ(full->inlier_threshold(), static_cast<float>(o.weight.eps_m));
  EXPECT_TRUE(r.refine.accepted);
  EXPECT_LT(r.refine.weight_before, 0.5 * r.refine.weight_after);
  EXPECT_LT((r.T_cam_obj.t - s.T_gt.t).norm(), 0.001);

  // The same start weighed at the filter's threshold (accept_eps_m 0) already has nearly all its
  // pixels as inliers.
  o.refine.accept_eps_m = 0;
  const ObjectEstimate at_filter_eps = RefineEstimate(o.refine, *full, s.frame.depth, e);
  EXPECT_GT(at_filter_eps.refine.weight_before, 2 * r.refine.weight_before);
}

}  // namespace
}  // namespace mcpose::engine

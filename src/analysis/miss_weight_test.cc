// Misses on a synthetic scene: an estimate moved off the object weighs less than the truth
// aligned to the depth (a search failure, in the box that holds the object); the aligned truth
// stays on the truth.
#include "mcpose/analysis/miss_weight.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include <gtest/gtest.h>

#include "mcpose/eval.h"
#include "synthetic_mesh.h"
#include "synthetic_scene.h"

namespace mcpose::analysis {
namespace {

struct Scene {
  Mesh mesh;
  testing::SyntheticFrame frame;
  SE3 T_gt{ExpSO3(Eigen::Vector3d(0.4, -0.3, 0.5)), Eigen::Vector3d(-0.02, 0.01, 0.7)};
  std::vector<Detection> boxes;
};

Scene MakeScene() {
  Scene s;
  testing::AddBox(&s.mesh, {-0.04f, -0.02f, -0.01f}, {0.08f, 0.05f, 0.03f});
  s.frame = testing::RenderFrame(s.mesh, s.T_gt, [](const Eigen::Vector3f&) { return Rgba8{128, 128, 128, 255}; }, 6);
  Detection object, distractor;
  EXPECT_GT(MaskBox(s.frame.visible, &object), 0);
  object.score = 0.6;
  distractor = object;
  distractor.x = object.x > 160 ? 5 : 315 - object.w;  // the other side of the image
  distractor.score = 0.7;
  s.boxes = {distractor, object};
  return s;
}

TEST(MissWeight, AnEstimateOffTheObjectIsASearchFailure) {
  const Scene s = MakeScene();
  ASSERT_EQ(s.boxes.size(), 2u);
  EstimatorOptions options;
  options.engine.threads = 1;
  Scorer context(options);
  const SE3 off{s.T_gt.R, s.T_gt.t + Eigen::Vector3d(0.03, 0, 0)};
  auto m = WeighMiss(context, s.frame.K, s.frame.depth, nullptr, s.mesh, s.boxes, off, s.T_gt);
  ASSERT_TRUE(m.ok()) << m.status().ToString();
  EXPECT_TRUE(m->search_failure());
  EXPECT_EQ(m->truth_box, 1);
  EXPECT_GT(m->truth_weight, m->estimate_weight + 0.1);
  EXPECT_LT(AddS(s.mesh.vertices_m, m->truth_aligned, s.T_gt), 0.0005);

  // The truth itself as the estimate: the two weigh the same, best in the object's box.
  auto same = WeighMiss(context, s.frame.K, s.frame.depth, nullptr, s.mesh, s.boxes, s.T_gt, s.T_gt);
  ASSERT_TRUE(same.ok());
  EXPECT_NEAR(same->estimate_weight, same->truth_weight, 0.005);
  EXPECT_EQ(same->estimate_box, 1);
}

TEST(MissWeight, TheBasinIsTheNearestProbeThatNoLongerOutweighsTheEstimate) {
  const Scene s = MakeScene();
  EstimatorOptions options;
  options.engine.threads = 1;
  Scorer context(options);
  const auto miss_at = [&](double dx) {
    const SE3 off{s.T_gt.R, s.T_gt.t + Eigen::Vector3d(dx, 0, 0)};
    auto m = WeighMiss(context, s.frame.K, s.frame.depth, nullptr, s.mesh, s.boxes, off, s.T_gt);
    EXPECT_TRUE(m.ok()) << m.status().ToString();
    return m.ok() ? *m : MissWeight{};
  };
  const MissWeight near = miss_at(0.01), far = miss_at(0.03);
  ASSERT_TRUE(near.search_failure());
  ASSERT_TRUE(far.search_failure());
  ASSERT_GT(near.estimate_weight, far.estimate_weight);
  const auto is_step = [](double v) {
    return std::isinf(v) || std::find(std::begin(kBasinSteps), std::end(kBasinSteps), v) != std::end(kBasinSteps);
  };
  for (const MissWeight& m : {near, far}) {
    EXPECT_TRUE(is_step(m.basin_turn_deg)) << m.basin_turn_deg;
    EXPECT_TRUE(is_step(m.basin_shift_mm)) << m.basin_shift_mm;
  }
  // The truth moved 20 mm along x lies 10 mm beyond the near estimate: it weighs less.
  EXPECT_LE(near.basin_shift_mm, 20);
  // A heavier estimate is outweighed by nearer probes: its basin is no wider.
  EXPECT_LE(near.basin_shift_mm, far.basin_shift_mm);
  EXPECT_LE(near.basin_turn_deg, far.basin_turn_deg);

  // No search failure, no basin.
  auto same = WeighMiss(context, s.frame.K, s.frame.depth, nullptr, s.mesh, s.boxes, s.T_gt, s.T_gt);
  ASSERT_TRUE(same.ok());
  EXPECT_EQ(same->basin_turn_deg, 0);
  EXPECT_EQ(same->basin_shift_mm, 0);
}

TEST(MissWeight, NeedsABox) {
  const Scene s = MakeScene();
  EstimatorOptions options;
  options.engine.threads = 1;
  Scorer context(options);
  auto m = WeighMiss(context, s.frame.K, s.frame.depth, nullptr, s.mesh, {}, s.T_gt, s.T_gt);
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.status().message().find("no box"), std::string::npos);
}

}  // namespace
}  // namespace mcpose::analysis

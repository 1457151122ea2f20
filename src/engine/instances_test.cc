#include "engine/instances.h"

#include <gtest/gtest.h>

#include "synthetic_mesh.h"
#include "synthetic_scene.h"

namespace mcpose::engine {
namespace {

Detection Box(double x, double y, double w, double h, double score) {
  Detection d;
  d.x = x, d.y = y, d.w = w, d.h = h, d.score = score;
  return d;
}

TEST(Instances, BoxIouOfKnownOverlaps) {
  EXPECT_DOUBLE_EQ(BoxIou(Box(0, 0, 10, 10, 1), Box(0, 0, 10, 10, 1)), 1.0);
  EXPECT_DOUBLE_EQ(BoxIou(Box(0, 0, 10, 10, 1), Box(5, 0, 10, 10, 1)), 50.0 / 150.0);
  EXPECT_DOUBLE_EQ(BoxIou(Box(0, 0, 10, 10, 1), Box(10, 0, 10, 10, 1)), 0.0);  // touching sides
  EXPECT_DOUBLE_EQ(BoxIou(Box(0, 0, 10, 10, 1), Box(20, 20, 5, 5, 1)), 0.0);
}

TEST(Instances, BoxesClusterAroundTheirBestScoredLeader) {
  // Two boxes of one object (IoU 0.82), one of a second object beside it, a lone low-scored one.
  const std::vector<Detection> boxes = {Box(0, 0, 100, 100, 0.6), Box(5, 5, 100, 100, 0.9),
                                        Box(110, 0, 100, 100, 0.7), Box(400, 300, 50, 50, 0.1)};
  const auto clusters = ClusterBoxes(boxes);
  ASSERT_EQ(clusters.size(), 3u);
  EXPECT_EQ(clusters[0], (std::vector<int>{1, 0}));  // leader first, clusters by leader score
  EXPECT_EQ(clusters[1], (std::vector<int>{2}));
  EXPECT_EQ(clusters[2], (std::vector<int>{3}));
  // A stricter overlap splits the first object's boxes; ties keep the earlier box first.
  EXPECT_EQ(ClusterBoxes(boxes, 0.9).size(), 4u);
  const std::vector<Detection> tied = {Box(0, 0, 10, 10, 0.5), Box(50, 0, 10, 10, 0.5)};
  EXPECT_EQ(ClusterBoxes(tied), (std::vector<std::vector<int>>{{0}, {1}}));
  EXPECT_TRUE(ClusterBoxes(std::vector<Detection>{}).empty());
}

TEST(Instances, SharedShareCountsTheCommonPixels) {
  const std::vector<int> a = {1, 3, 5, 7}, b = {3, 4, 5, 6};
  EXPECT_DOUBLE_EQ(SharedShare(a, b), 0.5);
  EXPECT_DOUBLE_EQ(SharedShare(b, a), 0.5);
  EXPECT_DOUBLE_EQ(SharedShare(a, a), 1.0);
  EXPECT_DOUBLE_EQ(SharedShare(a, std::vector<int>{}), 0.0);
  EXPECT_DOUBLE_EQ(SharedShare(std::vector<int>{}, a), 1.0);  // explains nothing: adds nothing
}

TEST(Instances, APoseExplainsTheDepthItsMeshMatches) {
  const Mesh box = testing::LatticeBox(Eigen::Vector3f(-0.05f, -0.04f, -0.03f), Eigen::Vector3f(0.05f, 0.04f, 0.03f), 2,
                                       [](int, const Eigen::Vector3f&) { return Rgba8{128, 128, 128, 255}; });
  const SE3 T(Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix(),
              Eigen::Vector3d(0.0, 0.0, 0.7));
  const testing::SyntheticFrame f = testing::RenderFrame(box, T, [](const Eigen::Vector3f&) { return Rgba8{}; }, 3);
  const std::vector<int> at_truth = ExplainedPixels(box, T, f.K, f.depth, 0.01);
  int object_pixels = 0;
  for (uint8_t v : f.visible.values) object_pixels += v != 0;
  ASSERT_GT(object_pixels, 1000);
  EXPECT_EQ(static_cast<int>(at_truth.size()), object_pixels);
  EXPECT_TRUE(std::is_sorted(at_truth.begin(), at_truth.end()));
  // 5 cm nearer the camera the mesh matches no depth; 2 cm aside it shares some pixels only.
  EXPECT_TRUE(ExplainedPixels(box, SE3(T.R, T.t - Eigen::Vector3d(0, 0, 0.05)), f.K, f.depth, 0.01).empty());
  const std::vector<int> aside = ExplainedPixels(box, SE3(T.R, T.t + Eigen::Vector3d(0.06, 0, 0)), f.K, f.depth, 0.01);
  EXPECT_LT(SharedShare(at_truth, aside), kSameObjectShare);
}

}  // namespace
}  // namespace mcpose::engine

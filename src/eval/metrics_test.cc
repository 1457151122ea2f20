#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "mcpose/eval.h"

namespace mcpose {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::vector<Eigen::Vector3f> RandomPoints(int n, std::mt19937& gen, float half_extent_m = 0.05f) {
  std::uniform_real_distribution<float> u(-half_extent_m, half_extent_m);
  std::vector<Eigen::Vector3f> pts;
  for (int i = 0; i < n; ++i) pts.emplace_back(u(gen), u(gen), u(gen));
  return pts;
}

SE3 RandomPose(std::mt19937& gen) {
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), t(-0.2, 0.2);
  const Eigen::Vector3d axis = Eigen::Vector3d(t(gen), t(gen), t(gen)).normalized();
  const Eigen::Matrix3d R = Eigen::AngleAxisd(angle(gen), axis).toRotationMatrix();
  return SE3(R, Eigen::Vector3d(t(gen), t(gen), 0.8 + t(gen)));
}

// Points on a circle of radius r in the z = 0 plane, at angles 2 pi k / n.
std::vector<Eigen::Vector3f> CirclePoints(int n, double radius_m) {
  std::vector<Eigen::Vector3f> pts;
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * M_PI * k / n;
    pts.emplace_back(static_cast<float>(radius_m * std::cos(a)),
                     static_cast<float>(radius_m * std::sin(a)), 0.0f);
  }
  return pts;
}

double BruteForceAddS(const std::vector<Eigen::Vector3f>& pts, const SE3& T_est, const SE3& T_gt) {
  double sum = 0;
  for (const auto& p : pts) {
    const Eigen::Vector3d q = T_gt * p.cast<double>();
    double best = kInf;
    for (const auto& r : pts) best = std::min(best, (T_est * r.cast<double>() - q).norm());
    sum += best;
  }
  return sum / static_cast<double>(pts.size());
}

TEST(EvalAdd, IdenticalPosesGiveZero) {
  std::mt19937 gen(1);
  const auto pts = RandomPoints(300, gen);
  for (int trial = 0; trial < 10; ++trial) {
    const SE3 T = RandomPose(gen);
    EXPECT_EQ(Add(pts, T, T), 0.0);
    EXPECT_EQ(AddS(pts, T, T), 0.0);
  }
}

TEST(EvalAdd, PureTranslationOffsetGivesItsLength) {
  std::mt19937 gen(2);
  const auto pts = RandomPoints(300, gen);
  const SE3 T_gt = RandomPose(gen);
  const Eigen::Vector3d d(0.003, -0.012, 0.004);  // 13 mm
  const SE3 T_est(T_gt.R, T_gt.t + d);
  EXPECT_NEAR(Add(pts, T_est, T_gt), d.norm(), 1e-12);
  EXPECT_NEAR(Add(pts, T_gt, T_est), d.norm(), 1e-12);
}

TEST(EvalAdd, EmptyPointSetGivesZero) {
  const SE3 T_est(Eigen::Matrix3d::Identity(), Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(Add({}, T_est, SE3()), 0.0);
  EXPECT_EQ(AddS({}, T_est, SE3()), 0.0);
}

TEST(EvalAddS, NeverExceedsAdd) {
  std::mt19937 gen(3);
  for (int trial = 0; trial < 50; ++trial) {
    const auto pts = RandomPoints(200, gen);
    const SE3 T_gt = RandomPose(gen);
    const SE3 T_est = RandomPose(gen);
    EXPECT_LE(AddS(pts, T_est, T_gt), Add(pts, T_est, T_gt) + 1e-12);
  }
}

TEST(EvalAddS, SymmetricCircleRotatedAboutItsAxisIsZero) {
  const int n = 360;
  const auto pts = CirclePoints(n, 0.05);
  std::mt19937 gen(4);
  const SE3 T_gt = RandomPose(gen);
  // A rotation of the model by 37 steps of the point spacing about its own z axis.
  const Eigen::Matrix3d R_z = Eigen::AngleAxisd(2.0 * M_PI * 37 / n, Eigen::Vector3d::UnitZ())
                                  .toRotationMatrix();
  const SE3 T_est(T_gt.R * R_z, T_gt.t);
  EXPECT_LT(AddS(pts, T_est, T_gt), 1e-6);
  EXPECT_GT(Add(pts, T_est, T_gt), 0.03);  // chord of 37 degrees on a 5 cm circle: 3.2 cm

  // Any angle about the axis: AddS stays below half the point spacing (0.44 mm).
  const SE3 T_est2(
      T_gt.R * Eigen::AngleAxisd(1.2345, Eigen::Vector3d::UnitZ()).toRotationMatrix(), T_gt.t);
  EXPECT_LT(AddS(pts, T_est2, T_gt), 0.5 * 2.0 * M_PI * 0.05 / n);
  EXPECT_GT(Add(pts, T_est2, T_gt), 0.05);
}

TEST(EvalAddS, MatchesBruteForceNearestNeighbour) {
  std::mt19937 gen(5);
  for (int trial = 0; trial < 10; ++trial) {
    const auto pts = RandomPoints(400 + 50 * trial, gen);
    const SE3 T_gt = RandomPose(gen);
    // Near and far estimates: a small perturbation and an unrelated pose.
    const SE3 T_near(T_gt.R * Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()).toRotationMatrix(),
                     T_gt.t + Eigen::Vector3d(0.004, 0, -0.002));
    const SE3 T_far = RandomPose(gen);
    EXPECT_NEAR(AddS(pts, T_near, T_gt), BruteForceAddS(pts, T_near, T_gt), 1e-12);
    EXPECT_NEAR(AddS(pts, T_far, T_gt), BruteForceAddS(pts, T_far, T_gt), 1e-12);
  }
}

// A points file whose points repeat (each written many times, some more than others) gives the
// mean over every point, as brute force does; the search runs over the distinct points.
TEST(EvalAddS, RepeatedPointsGiveTheMeanOverEveryPoint) {
  std::mt19937 gen(7);
  const auto distinct = RandomPoints(300, gen);
  std::vector<Eigen::Vector3f> repeated;
  for (size_t i = 0; i < distinct.size(); ++i)
    for (size_t k = 0; k < 1 + i % 7; ++k) repeated.push_back(distinct[(i * 37) % distinct.size()]);
  const SE3 T_gt = RandomPose(gen), T_est = RandomPose(gen);
  EXPECT_NEAR(AddS(repeated, T_est, T_gt), BruteForceAddS(repeated, T_est, T_gt), 1e-12);
  const std::vector<Eigen::Vector3f> same(5000, distinct[0]);
  EXPECT_NEAR(AddS(same, T_est, T_gt), (T_est * distinct[0].cast<double>() - T_gt * distinct[0].cast<double>()).norm(),
              1e-12);
}

TEST(EvalAddS, NonFinitePoseIsInfinite) {
  const auto pts = CirclePoints(10, 0.05);
  SE3 T_bad;
  T_bad.t.x() = std::nan("");
  EXPECT_EQ(AddS(pts, T_bad, SE3()), kInf);
  EXPECT_EQ(AddS(pts, SE3(), T_bad), kInf);
}

TEST(EvalAuc, HandComputedExamples) {
  EXPECT_DOUBLE_EQ(AccuracyAuc({0.0, 0.05}, 0.1), 0.75);        // (0.1 + 0.05) / (2 * 0.1)
  EXPECT_DOUBLE_EQ(AccuracyAuc({0.0, 0.0, 0.0}, 0.1), 1.0);
  EXPECT_DOUBLE_EQ(AccuracyAuc({0.1}, 0.1), 0.0);               // acc(x) = 0 for x < 0.1
  EXPECT_DOUBLE_EQ(AccuracyAuc({0.5}, 0.1), 0.0);
  EXPECT_DOUBLE_EQ(AccuracyAuc({0.02, kInf, 0.08, 0.5}, 0.1), (0.08 + 0.02) / (4 * 0.1));
  EXPECT_DOUBLE_EQ(AccuracyAuc({0.03}, 0.06), 0.5);
}

TEST(EvalAuc, InfinityAndEmptyInputGiveZero) {
  EXPECT_EQ(AccuracyAuc({kInf}, 0.1), 0.0);
  EXPECT_EQ(AccuracyAuc({kInf, kInf}, 0.1), 0.0);
  EXPECT_EQ(AccuracyAuc({}, 0.1), 0.0);
  EXPECT_DOUBLE_EQ(AccuracyAuc({0.0, kInf}, 0.1), 0.5);
  EXPECT_EQ(AccuracyAuc({std::nan("")}, 0.1), 0.0);
  EXPECT_EQ(AccuracyAuc({0.0}, 0.0), 0.0);
}

TEST(EvalAuc, MatchesNumericalIntegrationOfTheAccuracyCurve) {
  std::mt19937 gen(6);
  std::uniform_real_distribution<double> u(0.0, 0.15);
  std::vector<double> errors;
  for (int i = 0; i < 200; ++i) errors.push_back(i % 10 == 0 ? kInf : u(gen));
  const double max_m = 0.1;
  // Midpoint rule on acc(x) = share of errors < x.
  const int steps = 100000;
  double area = 0;
  for (int s = 0; s < steps; ++s) {
    const double x = (s + 0.5) * max_m / steps;
    int below = 0;
    for (double e : errors) below += e < x ? 1 : 0;
    area += static_cast<double>(below) / errors.size() * (max_m / steps);
  }
  EXPECT_NEAR(AccuracyAuc(errors, max_m), area / max_m, 1e-4);
}

TEST(EvalSymmetric, YcbvSymmetricObjectIds) {
  EXPECT_EQ(YcbvSymmetricObjectIds(), (std::set<int>{13, 16, 19, 20, 21}));
  EXPECT_EQ(EvalOptions().symmetric_obj_ids, YcbvSymmetricObjectIds());
  EXPECT_DOUBLE_EQ(EvalOptions().auc_max_m, 0.10);
}

}  // namespace
}  // namespace mcpose

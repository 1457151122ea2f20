#include "score/box_fit.h"

#include <cmath>

#include <gtest/gtest.h>

#include "core/rng.h"
#include "mcpose/se3.h"
#include "synthetic_mesh.h"

namespace mcpose::score {
namespace {

const Intrinsics kK{600, 600, 160, 120, 320, 240};

// The bounding rectangle of every vertex of `mesh` at (R, t), projected: what the extreme
// points' rectangle approximates from inside.
FitBox ProjectedRect(const Mesh& mesh, const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
  FitBox r{INFINITY, INFINITY, -INFINITY, -INFINITY};
  for (const Eigen::Vector3f& v : mesh.vertices_m) {
    const Eigen::Vector3d c = R * v.cast<double>() + t;
    const double u = kK.fx * c.x() / c.z() + kK.cx, w = kK.fy * c.y() / c.z() + kK.cy;
    r.x0 = std::min(r.x0, u), r.x1 = std::max(r.x1, u), r.y0 = std::min(r.y0, w), r.y1 = std::max(r.y1, w);
  }
  return r;
}

TEST(BoxFit, ExtremePointsBoundTheProjectionFromInsideAndCloseToIt) {
  const Mesh mesh = testing::Blob();
  const std::vector<Eigen::Vector3d> extremes = ExtremePoints(mesh);
  ASSERT_EQ(extremes.size(), 26u);
  Rng rng(3, 3);
  for (int k = 0; k < 50; ++k) {
    const Eigen::Matrix3d R = ExpSO3(Eigen::Vector3d(rng.Normal(), rng.Normal(), rng.Normal()));
    const Eigen::Vector3d t(rng.Uniform(-0.05, 0.05), rng.Uniform(-0.05, 0.05), rng.Uniform(0.4, 0.8));
    const FitBox all = ProjectedRect(mesh, R, t);
    // Inside the whole projection's rectangle, the share is 1; in its left half, about a half
    // of the extreme points' rectangle.
    EXPECT_DOUBLE_EQ(BoxFitShare(extremes, R, t, kK, all), 1.0) << k;
    FitBox left = all;
    left.x1 = 0.5 * (all.x0 + all.x1);
    const double half = BoxFitShare(extremes, R, t, kK, left);
    EXPECT_GT(half, 0.4) << k;
    EXPECT_LT(half, 0.6) << k;
    // A box 15 % smaller on every side holds 0.7^2 of the whole rectangle; of the extreme
    // points' rectangle, unless that is much smaller than the whole, not much more.
    const double mx = 0.15 * (all.x1 - all.x0), my = 0.15 * (all.y1 - all.y0);
    const double shrunk = BoxFitShare(extremes, R, t, kK, FitBox{all.x0 + mx, all.y0 + my, all.x1 - mx, all.y1 - my});
    EXPECT_LT(shrunk, 0.7) << k;
  }
}

TEST(BoxFit, FarOutsideOrBehindTheCameraIsZero) {
  const std::vector<Eigen::Vector3d> extremes = ExtremePoints(testing::Blob());
  const FitBox box{0, 0, 50, 50};
  EXPECT_EQ(BoxFitShare(extremes, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 0.5), kK, box), 0.0);
  EXPECT_EQ(BoxFitShare(extremes, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 0.03), kK, FitBox{-1e9, -1e9, 1e9, 1e9}),
            0.0);
}

TEST(BoxFit, SidesAtTheImageBorderAreOpen) {
  const FitBox inner = FitBoxOf(Detection{0, 0, 1, 0.5, 10, 20, 100, 50}, kK);
  EXPECT_EQ(inner.x0, 10);
  EXPECT_EQ(inner.y1, 70);
  const FitBox corner = FitBoxOf(Detection{0, 0, 1, 0.5, 0, 0.5, 320, 100}, kK);
  EXPECT_EQ(corner.x0, -INFINITY);
  EXPECT_EQ(corner.y0, -INFINITY);
  EXPECT_EQ(corner.x1, INFINITY);
  EXPECT_EQ(corner.y1, 100.5);
  // The blob half out of the image on the left, its box cut at the border: it fits.
  const std::vector<Eigen::Vector3d> extremes = ExtremePoints(testing::Blob());
  const Eigen::Vector3d t(-160 * 0.5 / 600, 0, 0.5);  // centred on the image's left edge
  EXPECT_DOUBLE_EQ(BoxFitShare(extremes, Eigen::Matrix3d::Identity(), t, kK, FitBoxOf(Detection{0, 0, 1, 0.5, 0, 30, 120, 180}, kK)),
                   1.0);
}

TEST(BoxFit, FactorIsOneAboveTheThresholdAndProportionalBelow) {
  EXPECT_EQ(BoxFitFactor(0.9, 0.8), 1.0);
  EXPECT_EQ(BoxFitFactor(0.8, 0.8), 1.0);
  EXPECT_DOUBLE_EQ(BoxFitFactor(0.4, 0.8), 0.5);
  EXPECT_EQ(BoxFitFactor(0.0, 0.0), 1.0);  // off
}

}  // namespace
}  // namespace mcpose::score

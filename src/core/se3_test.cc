#include "mcpose/se3.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace mcpose {
namespace {

Eigen::Vector3d RandomAxis(std::mt19937_64& gen) {
  std::normal_distribution<double> n;
  return Eigen::Vector3d(n(gen), n(gen), n(gen)).normalized();
}

TEST(Se3, ExpLogRoundTripSO3) {
  std::mt19937_64 gen(1);
  std::uniform_real_distribution<double> angle(0.0, M_PI - 1e-6);
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d w = RandomAxis(gen) * angle(gen);
    const Eigen::Matrix3d R = ExpSO3(w);
    EXPECT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
    EXPECT_LT((LogSO3(R) - w).norm(), 1e-9) << "angle " << w.norm();
  }
}

TEST(Se3, SmallAndNearPiAngles) {
  std::mt19937_64 gen(2);
  for (double theta : {0.0, 1e-12, 1e-8, 1e-5, 1e-3, M_PI - 1e-3, M_PI - 1e-7}) {
    const Eigen::Vector3d w = RandomAxis(gen) * theta;
    const Eigen::Matrix3d R = ExpSO3(w);
    EXPECT_LT((ExpSO3(LogSO3(R)) - R).norm(), 1e-9) << theta;
    EXPECT_NEAR(LogSO3(R).norm(), theta, 1e-7) << theta;
  }
}

TEST(Se3, ExpLogRoundTripSE3) {
  std::mt19937_64 gen(3);
  std::normal_distribution<double> n;
  for (int i = 0; i < 500; ++i) {
    Vector6d xi;
    for (int k = 0; k < 6; ++k) xi[k] = n(gen);
    xi.tail<3>() = xi.tail<3>().normalized() * std::fmod(std::abs(xi[5]) + 0.1, 3.0);
    const SE3 T = SE3::Exp(xi);
    EXPECT_LT((T.Log() - xi).norm(), 1e-9);
    const SE3 I = T * T.Inverse();
    EXPECT_LT((I.Matrix() - Eigen::Matrix4d::Identity()).norm(), 1e-12);
  }
}

TEST(Se3, RotationAngle) {
  const Eigen::Matrix3d R = ExpSO3(Eigen::Vector3d(0, 0, 0.7));
  EXPECT_NEAR(RotationAngle(Eigen::Matrix3d::Identity(), R), 0.7, 1e-12);
  EXPECT_NEAR(RotationAngle(R, R), 0.0, 1e-12);
}

}  // namespace
}  // namespace mcpose

#include <algorithm>
#include <cmath>

#include "mcpose/se3.h"

namespace mcpose {

Eigen::Matrix3d Hat(const Eigen::Vector3d& w) {
  Eigen::Matrix3d W;
  W << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return W;
}

Eigen::Matrix3d ExpSO3(const Eigen::Vector3d& omega) {
  const double theta2 = omega.squaredNorm();
  const Eigen::Matrix3d W = Hat(omega);
  // Small angles: Taylor series of sin(θ)/θ and (1 - cos θ)/θ².
  if (theta2 < 1e-12) return Eigen::Matrix3d::Identity() + W + 0.5 * W * W;
  const double theta = std::sqrt(theta2);
  const double a = std::sin(theta) / theta;
  const double b = (1.0 - std::cos(theta)) / theta2;
  return Eigen::Matrix3d::Identity() + a * W + b * W * W;
}

Eigen::Vector3d LogSO3(const Eigen::Matrix3d& R) {
  // The quaternion route is stable at 0 and at π (Eigen picks the best-conditioned branch).
  Eigen::Quaterniond q(R);
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  const Eigen::Vector3d v = q.vec();
  const double s = v.norm();
  if (s < 1e-12) return 2.0 * v;  // θ ≈ 2 s for tiny angles
  const double theta = 2.0 * std::atan2(s, q.w());
  return v * (theta / s);
}

double RotationAngle(const Eigen::Matrix3d& R_a, const Eigen::Matrix3d& R_b) {
  return LogSO3(R_a.transpose() * R_b).norm();
}

Eigen::Matrix4d SE3::Matrix() const {
  Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
  M.topLeftCorner<3, 3>() = R;
  M.topRightCorner<3, 1>() = t;
  return M;
}

namespace {

// Left Jacobian of SO(3): V(ω) with t = V ρ.
Eigen::Matrix3d LeftJacobianSO3(const Eigen::Vector3d& omega) {
  const double theta2 = omega.squaredNorm();
  const Eigen::Matrix3d W = Hat(omega);
  if (theta2 < 1e-12) return Eigen::Matrix3d::Identity() + 0.5 * W + W * W / 6.0;
  const double theta = std::sqrt(theta2);
  const double b = (1.0 - std::cos(theta)) / theta2;
  const double c = (theta - std::sin(theta)) / (theta2 * theta);
  return Eigen::Matrix3d::Identity() + b * W + c * W * W;
}

}  // namespace

SE3 SE3::Exp(const Vector6d& xi) {
  const Eigen::Vector3d rho = xi.head<3>();
  const Eigen::Vector3d omega = xi.tail<3>();
  return SE3(ExpSO3(omega), LeftJacobianSO3(omega) * rho);
}

Vector6d SE3::Log() const {
  const Eigen::Vector3d omega = LogSO3(R);
  Vector6d xi;
  xi.head<3>() = LeftJacobianSO3(omega).inverse() * t;
  xi.tail<3>() = omega;
  return xi;
}

}  // namespace mcpose

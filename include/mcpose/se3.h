// Rigid transforms and their exponential map.
//
// Conventions (stated once, here):
//  * SE3 T_a_b maps points in frame b to frame a: X_a = R * X_b + t.  Poses of objects are
//    T_cam_obj (model to camera), translation in metres, OpenCV camera axes (x right, y down,
//    z forward).
//  * The tangent vector is ordered (translation ρ, rotation ω): xi = [ρ; ω] in R^6, as in Sophus.
//  * Diffusion perturbs on the left in the camera frame:  T' = Exp(xi) * T   is NOT used; instead
//    the estimator perturbs rotation about the object origin (R' = Exp(ω) R) and translation in
//    the camera frame (t' = t + δ), so a rotation step does not move the object centre.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace mcpose {

using Vector6d = Eigen::Matrix<double, 6, 1>;

// Rotation vector (axis * angle) -> rotation matrix, with a Taylor branch near zero.
Eigen::Matrix3d ExpSO3(const Eigen::Vector3d& omega);
// Rotation matrix -> rotation vector with angle in [0, pi]; stable near 0 and near pi.
Eigen::Vector3d LogSO3(const Eigen::Matrix3d& R);
// Skew-symmetric matrix [w]_x.
Eigen::Matrix3d Hat(const Eigen::Vector3d& w);
// Geodesic angle between two rotations in radians, in [0, pi].
double RotationAngle(const Eigen::Matrix3d& R_a, const Eigen::Matrix3d& R_b);

struct SE3 {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();

  SE3() = default;
  SE3(const Eigen::Matrix3d& R_in, const Eigen::Vector3d& t_in) : R(R_in), t(t_in) {}

  Eigen::Vector3d operator*(const Eigen::Vector3d& x) const { return R * x + t; }
  SE3 operator*(const SE3& o) const { return SE3(R * o.R, R * o.t + t); }
  SE3 Inverse() const { return SE3(R.transpose(), -(R.transpose() * t)); }
  Eigen::Matrix4d Matrix() const;

  // Group exponential of xi = [rho; omega] (with the SO(3) left Jacobian for the translation).
  static SE3 Exp(const Vector6d& xi);
  // Inverse of Exp.
  Vector6d Log() const;
};

}  // namespace mcpose

// Diffusion: Gaussian noise in 6-DoF. The rotation is perturbed on the tangent space about the
// object origin, R' = Exp(sigma_r * n_r) R, and the translation in the camera frame,
// t' = t + sigma_t * n_t, with n_r, n_t ~ N(0, I_3). A rotation step never moves the object
// origin, so the two noises stay independent. Flip moves (Flip, below) turn a pose 180 degrees
// about a model axis before its noise (DiffusionOptions::flip_rate).
#pragma once

#include <Eigen/Core>

#include "core/rng.h"
#include "mcpose/se3.h"

namespace mcpose::filter {

inline void Diffuse(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, double sigma_r_rad,
                    double sigma_t_m, Rng& rng, Eigen::Matrix3d* R_out, Eigen::Vector3d* t_out) {
  const Eigen::Vector3d n_r(rng.Normal(), rng.Normal(), rng.Normal());
  const Eigen::Vector3d n_t(rng.Normal(), rng.Normal(), rng.Normal());
  *R_out = ExpSO3(sigma_r_rad * n_r) * R;
  *t_out = t + sigma_t_m * n_t;
}

// A flip move: the pose turned 180 degrees about model axis `axis` (0, 1, 2) through the model
// point `center`, which stays where it was in the camera frame: R' = R F, t' = t + R (c - F c),
// F = diag(+-1) with -1 off the axis.
inline void Flip(int axis, const Eigen::Vector3d& center, Eigen::Matrix3d* R, Eigen::Vector3d* t) {
  Eigen::Vector3d f(-1, -1, -1);
  f[axis] = 1;
  const Eigen::Vector3d c_flipped = f.cwiseProduct(center);
  *t += *R * (center - c_flipped);
  *R = *R * f.asDiagonal();
}

}  // namespace mcpose::filter

// Particle storage (structure of arrays) and the two ping-pong buffers of the filter.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "mcpose/se3.h"

namespace mcpose::filter {

struct ParticleSet {
  std::vector<Eigen::Matrix3d> R_cam_obj;
  std::vector<Eigen::Vector3d> t_cam_obj_m;
  std::vector<int32_t> box;  // index of the box the sample is rendered in
  std::vector<double> weight;

  void Resize(size_t n) {
    R_cam_obj.resize(n);
    t_cam_obj_m.resize(n);
    box.resize(n);
    weight.assign(n, 0.0);
  }
  size_t size() const { return box.size(); }
  SE3 Pose(size_t i) const { return SE3(R_cam_obj[i], t_cam_obj_m[i]); }
};

// Uniform random rotation (Shoemake's method) from three uniforms in [0, 1).
Eigen::Matrix3d UniformRotation(double u1, double u2, double u3);

// Splits `total` samples over boxes in proportion to their scores (largest remainder; ties to
// the lower index). All scores must be > 0; returns one count per box, summing to total.
std::vector<int> AllocateSamples(const std::vector<double>& scores, int total);

}  // namespace mcpose::filter

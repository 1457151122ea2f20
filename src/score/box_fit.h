// Box fit: how much of a pose's projected object lies inside its detection box. The detector
// boxes what it saw of the object, so a pose whose object would reach far past the box is
// unlikely, however well its part inside the box fits the depth: a can's lid laid flush over a
// flat surface fills any box too small for the can and matches the surface's depth everywhere
// in it, while the real can lies elsewhere, partly hidden, in a box the detector scored lower.
#pragma once

#include <span>
#include <vector>

#include <Eigen/Core>

#include "mcpose/camera.h"
#include "mcpose/detection.h"
#include "mcpose/mesh.h"

namespace mcpose::score {

// The mesh's extreme vertices along the 26 directions (±1, 0) of a 3x3x3 grid, model frame:
// their projected bounding rectangle bounds most of the object's projection from below (it
// never exceeds the object's own), at 26 projections a pose.
std::vector<Eigen::Vector3d> ExtremePoints(const Mesh& mesh);

// A detection box in image pixels, its sides at the image border open (an object cut by the
// border may reach past it).
struct FitBox {
  double x0, y0, x1, y1;
};
FitBox FitBoxOf(const Detection& d, const Intrinsics& K);

// The share of the bounding rectangle of `extremes` projected at pose (R, t) that lies inside
// `box`, in [0, 1]; 0 when a point lies behind the near plane (5 cm), 1 for an empty rectangle.
double BoxFitShare(std::span<const Eigen::Vector3d> extremes, const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
                   const Intrinsics& K, const FitBox& box);

// The factor the weight is multiplied by: min(1, share / box_fit); 1 when box_fit is 0 (off).
inline double BoxFitFactor(double share, double box_fit) {
  return box_fit > 0 && share < box_fit ? share / box_fit : 1.0;
}

}  // namespace mcpose::score

// How a rigid object comes to rest on a horizontal plane: on a face of its convex hull whose
// plane has the centre of mass above the face itself (so it does not tip over), the face's
// potential being the height of the centre of mass over it. A dropped object ends on one of these;
// the lowest is the likeliest.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "mcpose/mesh.h"
#include "mcpose/status.h"

namespace mcpose {

struct RestPose {
  // Model to rest frame: the rest frame's +z is up, the plane is z = 0, and the centre of mass
  // lies on the z axis: X_rest = R (X_model - centre_of_mass) + (0, 0, height).
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  double height = 0;      // centre of mass over the plane, metres (the potential)
  double face_area = 0;   // of the hull face it rests on, square metres
};

// The centre of mass of a closed mesh of uniform density (the mean vertex when the mesh encloses
// no volume).
Eigen::Vector3d CentreOfMass(const Mesh& mesh);

// The stable rest poses of `mesh`, lowest first: one per convex-hull face (coplanar facets
// merged) whose plane's foot of the centre of mass lies inside the face, at least `min_margin_m`
// from its edges. An error if the hull cannot be built (fewer than four points not in a plane).
StatusOr<std::vector<RestPose>> StableRestPoses(const Mesh& mesh, double min_margin_m = 0.0005);

}  // namespace mcpose

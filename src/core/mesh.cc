#include <cmath>
#include <string>

#include "mcpose/mesh.h"

#include <Eigen/Geometry>

namespace mcpose {

Eigen::Vector3f Mesh::BoundsMin() const {
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(INFINITY);
  for (const auto& v : vertices_m) lo = lo.cwiseMin(v);
  return lo;
}

Eigen::Vector3f Mesh::BoundsMax() const {
  Eigen::Vector3f hi = Eigen::Vector3f::Constant(-INFINITY);
  for (const auto& v : vertices_m) hi = hi.cwiseMax(v);
  return hi;
}

Status Mesh::Validate(const std::string& source) const {
  if (vertices_m.empty() || triangles.empty()) {
    return InvalidArgument(source + ": mesh is empty (" + std::to_string(vertices_m.size()) +
                           " vertices, " + std::to_string(triangles.size()) + " triangles)");
  }
  for (size_t i = 0; i < vertices_m.size(); ++i) {
    if (!vertices_m[i].allFinite()) {
      return InvalidArgument(source + ": vertex " + std::to_string(i) + " is not finite");
    }
  }
  const size_t n = vertices_m.size();
  size_t non_degenerate = 0;
  for (size_t i = 0; i < triangles.size(); ++i) {
    const auto& tri = triangles[i];
    if (tri[0] >= n || tri[1] >= n || tri[2] >= n) {
      return InvalidArgument(source + ": triangle " + std::to_string(i) +
                             " refers to a vertex index beyond the " + std::to_string(n) +
                             " vertices");
    }
    const Eigen::Vector3f e1 = vertices_m[tri[1]] - vertices_m[tri[0]];
    const Eigen::Vector3f e2 = vertices_m[tri[2]] - vertices_m[tri[0]];
    if (e1.cross(e2).squaredNorm() > 0.f) ++non_degenerate;
  }
  if (non_degenerate == 0) {
    return InvalidArgument(source + ": mesh is degenerate (all " +
                           std::to_string(triangles.size()) + " triangles have zero area)");
  }
  const MeshAppearance& a = appearance;
  if (a.has_vertex_colours() && a.vertex_colours.size() != n)
    return InvalidArgument(source + ": " + std::to_string(a.vertex_colours.size()) + " vertex colours for " +
                           std::to_string(n) + " vertices");
  if (!a.triangle_uv.empty() && a.triangle_uv.size() != triangles.size())
    return InvalidArgument(source + ": texture coordinates for " + std::to_string(a.triangle_uv.size()) +
                           " of " + std::to_string(triangles.size()) + " triangles");
  const Eigen::Vector3f extent = BoundsMax() - BoundsMin();
  if (!(extent.maxCoeff() > 0.f)) {
    return InvalidArgument(source + ": mesh is degenerate (all vertices coincide)");
  }
  return Status::Ok();
}

}  // namespace mcpose

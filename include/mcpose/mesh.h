// Triangle meshes in metres, counter-clockwise winding seen from outside.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mcpose/status.h"

namespace mcpose {

struct Mesh {
  std::vector<Eigen::Vector3f> vertices_m;
  std::vector<std::array<uint32_t, 3>> triangles;

  // Axis-aligned bounds of the vertices (metres). Undefined for an empty mesh.
  Eigen::Vector3f BoundsMin() const;
  Eigen::Vector3f BoundsMax() const;

  // Ok, or an error naming `source` if the mesh is empty, has an index out of range, a
  // non-finite vertex, or no triangle of non-zero area (degenerate). Zero-area triangles
  // among valid ones are allowed (040_large_marker has 162).
  Status Validate(const std::string& source) const;
};

}  // namespace mcpose

// Synthetic meshes for unit tests: axis-aligned boxes, wound counter-clockwise seen from outside.
#pragma once

#include <cstdint>

#include "mcpose/mesh.h"

namespace mcpose::testing {

// Appends the box [lo, hi] (8 vertices, 12 triangles) to *m.
inline void AddBox(Mesh* m, Eigen::Vector3f lo, Eigen::Vector3f hi) {
  const uint32_t base = static_cast<uint32_t>(m->vertices_m.size());
  for (int i = 0; i < 8; ++i)
    m->vertices_m.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
  const uint32_t f[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                             {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (const auto& t : f) m->triangles.push_back({base + t[0], base + t[1], base + t[2]});
}

}  // namespace mcpose::testing

// Synthetic meshes for unit tests, wound counter-clockwise seen from outside: axis-aligned boxes
// and a bumpy closed blob.
#pragma once

#include <cmath>
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

// A closed, finely tessellated ellipsoid-ish blob (outward, counter-clockwise), metres.
inline Mesh Blob() {
  Mesh m;
  const int nu = 48, nv = 24;
  for (int j = 0; j <= nv; ++j) {
    const double th = M_PI * j / nv;
    for (int i = 0; i < nu; ++i) {
      const double ph = 2 * M_PI * i / nu;
      const double r = 0.05 * (1 + 0.2 * std::sin(3 * ph) * std::sin(th));
      m.vertices_m.emplace_back(r * std::sin(th) * std::cos(ph), 0.7 * r * std::sin(th) * std::sin(ph),
                                1.4 * r * std::cos(th));
    }
  }
  auto id = [&](int i, int j) { return static_cast<uint32_t>(j * nu + (i % nu)); };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      m.triangles.push_back({id(i, j), id(i, j + 1), id(i + 1, j)});
      m.triangles.push_back({id(i + 1, j), id(i, j + 1), id(i + 1, j + 1)});
    }
  return m;
}

}  // namespace mcpose::testing

// Synthetic meshes for unit tests, wound counter-clockwise seen from outside: axis-aligned boxes
// and a bumpy closed blob.
#pragma once

#include <array>
#include <cmath>
#include <utility>
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

// The box [lo, hi] with each face a lattice of n x n squares of its own vertices, coloured by
// `colour_of(face, vertex)` (vertex colours; faces 0-5: -x, +x, -y, +y, -z, +z): a box with a
// colour pattern the colour grid can hold.
template <typename ColourOf>
inline Mesh LatticeBox(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, int n, ColourOf colour_of) {
  Mesh box;
  for (int f = 0; f < 6; ++f) {
    const int a = f / 2, b = (a + 1) % 3, c = (a + 2) % 3;
    const uint32_t base = static_cast<uint32_t>(box.vertices_m.size());
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        Eigen::Vector3f p;
        p[a] = f % 2 ? hi[a] : lo[a];
        p[b] = lo[b] + (hi[b] - lo[b]) * i / n, p[c] = lo[c] + (hi[c] - lo[c]) * j / n;
        box.vertices_m.push_back(p);
        box.appearance.vertex_colours.push_back(colour_of(f, p));
      }
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const uint32_t v = base + j * (n + 1) + i;
        std::array<uint32_t, 3> t0 = {v, v + 1, v + n + 2}, t1 = {v, v + n + 2, v + n + 1};
        if (f % 2 == 0) std::swap(t0[1], t0[2]), std::swap(t1[1], t1[2]);
        box.triangles.push_back(t0), box.triangles.push_back(t1);
      }
  }
  return box;
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

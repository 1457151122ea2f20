#include "score/colour_grid.h"

#include <cmath>

#include <gtest/gtest.h>

#include "core/rng.h"
#include "synthetic_mesh.h"

namespace mcpose::appearance {
namespace {

ColourImage RandomTexture(Rng& rng, int w, int h, bool holes) {
  ColourImage t;
  t.width = w, t.height = h;
  t.rgba.resize(4 * static_cast<size_t>(w) * h);
  for (size_t i = 0; i < t.rgba.size(); ++i) t.rgba[i] = static_cast<uint8_t>(rng.NextU64());
  for (size_t i = 3; i < t.rgba.size(); i += 4) t.rgba[i] = holes && rng.Uniform() < 0.3 ? 0 : 255;
  return t;
}

// Bilinear texture sampling against a brute-force reference: every texel weighted by the
// tent function of its distance to the sample point (the same bilinear filter, written as a
// sum over the whole image), alpha-weighted colour.
TEST(ColourGrid, TextureSamplingMatchesABruteForceTentFilter) {
  Rng rng(5, 5);
  for (bool holes : {false, true}) {
    const ColourImage t = RandomTexture(rng, 13, 9, holes);
    for (int k = 0; k < 300; ++k) {
      const Eigen::Vector2f uv(static_cast<float>(rng.Uniform(0.1, 0.9)), static_cast<float>(rng.Uniform(0.1, 0.9)));
      const Rgba8 fast = SampleTexture(t, uv);
      const double px = uv.x() * t.width - 0.5, py = (1 - uv.y()) * t.height - 0.5;
      double s[3] = {0, 0, 0}, a = 0;
      for (int y = 0; y < t.height; ++y)
        for (int x = 0; x < t.width; ++x) {
          const double w = std::max(0.0, 1 - std::fabs(x - px)) * std::max(0.0, 1 - std::fabs(y - py));
          const uint8_t* p = t.at(x, y);
          for (int c = 0; c < 3; ++c) s[c] += w * p[3] * p[c];
          a += w * p[3];
        }
      ASSERT_NEAR(fast.a, a, 0.51) << k;
      if (a < 1) continue;
      ASSERT_NEAR(fast.r, s[0] / a, 0.51) << k;
      ASSERT_NEAR(fast.g, s[1] / a, 0.51) << k;
      ASSERT_NEAR(fast.b, s[2] / a, 0.51) << k;
    }
  }
  EXPECT_EQ(SampleTexture(RandomTexture(rng, 4, 4, false), Eigen::Vector2f(NAN, 0.5f)).a, 0);
}

// Vertex colours interpolated at random barycentric points of random triangles, against the
// plain formula.
TEST(ColourGrid, VertexColourInterpolationMatchesTheBarycentricFormula) {
  Rng rng(6, 6);
  Mesh m;
  testing::AddBox(&m, {-0.05f, -0.03f, -0.02f}, {0.05f, 0.03f, 0.02f});
  for (size_t v = 0; v < m.vertices_m.size(); ++v)
    m.appearance.vertex_colours.push_back({static_cast<uint8_t>(rng.NextU64()), static_cast<uint8_t>(rng.NextU64()),
                                           static_cast<uint8_t>(rng.NextU64()), 255});
  for (int k = 0; k < 500; ++k) {
    const size_t t = static_cast<size_t>(rng.Uniform() * m.triangles.size());
    const double u = rng.Uniform(), v = rng.Uniform() * (1 - u);
    const Eigen::Vector3f b(static_cast<float>(1 - u - v), static_cast<float>(u), static_cast<float>(v));
    const Rgba8 c = SurfaceColour(m, t, b);
    for (int ch = 0; ch < 3; ++ch) {
      double expected = 0;
      for (int i = 0; i < 3; ++i) {
        const Rgba8& vc = m.appearance.vertex_colours[m.triangles[t][i]];
        expected += b[i] * (ch == 0 ? vc.r : ch == 1 ? vc.g : vc.b);
      }
      const int got = ch == 0 ? c.r : ch == 1 ? c.g : c.b;
      ASSERT_NEAR(got, expected, 0.51) << k;
    }
    EXPECT_EQ(c.a, 255);
  }
}

// A box whose faces have one colour each (as vertex colours cannot: each face gets its own
// vertices): the grid recovers each face's colour at points on that face, away from the
// edges, and says nothing (unknown) far from the surface.
TEST(ColourGrid, BakedGridGivesEachFaceItsColour) {
  Mesh m;
  const Eigen::Vector3f lo(-0.06f, -0.04f, -0.03f), hi(0.06f, 0.04f, 0.03f);
  const Rgba8 colours[6] = {{200, 30, 30, 255}, {30, 200, 30, 255}, {30, 30, 200, 255},
                            {200, 200, 30, 255}, {30, 200, 200, 255}, {200, 30, 200, 255}};
  // Face f: axis f / 2 at lo (even f) or hi (odd f), split in a fine lattice of triangles.
  for (int f = 0; f < 6; ++f) {
    const int a = f / 2, b = (a + 1) % 3, c = (a + 2) % 3;
    const int n = 20;
    const uint32_t base = static_cast<uint32_t>(m.vertices_m.size());
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        Eigen::Vector3f p;
        p[a] = f % 2 ? hi[a] : lo[a];
        p[b] = lo[b] + (hi[b] - lo[b]) * i / n;
        p[c] = lo[c] + (hi[c] - lo[c]) * j / n;
        m.vertices_m.push_back(p);
        m.appearance.vertex_colours.push_back(colours[f]);
      }
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const uint32_t v = base + j * (n + 1) + i;
        m.triangles.push_back({v, v + 1, v + n + 2});
        m.triangles.push_back({v, v + n + 2, v + n + 1});
      }
  }
  ASSERT_TRUE(m.Validate("box").ok());
  const auto grid = ColourGrid::Build(m);
  ASSERT_NE(grid, nullptr);
  EXPECT_GT(grid->known_fraction(), 0.99);
  Rng rng(7, 7);
  const float margin = 3 * grid->cell_m();
  for (int k = 0; k < 600; ++k) {
    const int f = k % 6, a = f / 2, b = (a + 1) % 3, c = (a + 2) % 3;
    Eigen::Vector3f p;
    p[a] = f % 2 ? hi[a] : lo[a];
    p[b] = static_cast<float>(rng.Uniform(lo[b] + margin, hi[b] - margin));
    p[c] = static_cast<float>(rng.Uniform(lo[c] + margin, hi[c] - margin));
    // Half a cell off the surface, as a simplified mesh's rendered point can be.
    p[a] += static_cast<float>(rng.Uniform(-0.5, 0.5)) * grid->cell_m();
    EXPECT_EQ(grid->At(p), colours[f]) << "face " << f;
  }
  EXPECT_EQ(grid->At(Eigen::Vector3f::Zero()).a, 0);  // the middle of the box: no surface
  EXPECT_EQ(grid->At(Eigen::Vector3f(1, 1, 1)).a, 0);  // outside the grid
  Mesh plain = m;
  plain.appearance = MeshAppearance{};
  EXPECT_EQ(ColourGrid::Build(plain), nullptr);
}

}  // namespace
}  // namespace mcpose::appearance

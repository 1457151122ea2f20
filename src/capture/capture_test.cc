#include "mcpose/capture.h"

#include <cmath>

#include <gtest/gtest.h>

#include "score/colour_grid.h"
#include "synthetic_mesh.h"
#include "synthetic_scene.h"

namespace mcpose::appearance {
namespace {

// A smooth colour field over the model: what the synthetic camera sees on the surface.
Rgba8 Field(const Eigen::Vector3f& p) {
  auto byte = [](double v) { return static_cast<uint8_t>(std::clamp(v, 0.0, 255.0)); };
  return {byte(128 + 1500 * p.x()), byte(128 + 1500 * p.y()), byte(128 + 1500 * p.z()), 255};
}

// A box whose six faces are laid out side by side in texture space (a 3 x 2 atlas), as a
// scanned model's texture layout.
Mesh AtlasBox() {
  Mesh m;
  const Eigen::Vector3f lo(-0.05f, -0.035f, -0.025f), hi(0.05f, 0.035f, 0.025f);
  for (int f = 0; f < 6; ++f) {
    const int a = f / 2, b = (a + 1) % 3, c = (a + 2) % 3;
    const bool high = f % 2;
    const uint32_t base = static_cast<uint32_t>(m.vertices_m.size());
    Eigen::Vector2f uv[4];
    const float u0 = (f % 3) / 3.f, v0 = (f / 3) / 2.f;
    for (int k = 0; k < 4; ++k) {
      Eigen::Vector3f p;
      p[a] = high ? hi[a] : lo[a];
      p[b] = (k & 1) ? hi[b] : lo[b];
      p[c] = (k & 2) ? hi[c] : lo[c];
      m.vertices_m.push_back(p);
      uv[k] = {u0 + (0.02f + 0.29f * (k & 1)), v0 + (0.02f + 0.46f * ((k & 2) >> 1))};
    }
    // Outward winding: counter-clockwise seen from outside.
    std::array<uint32_t, 3> t0 = {base, base + 1, base + 3}, t1 = {base, base + 3, base + 2};
    std::array<Eigen::Vector2f, 3> uv0 = {uv[0], uv[1], uv[3]}, uv1 = {uv[0], uv[3], uv[2]};
    if (!high) std::swap(t0[1], t0[2]), std::swap(uv0[1], uv0[2]), std::swap(t1[1], t1[2]), std::swap(uv1[1], uv1[2]);
    m.triangles.push_back(t0), m.appearance.triangle_uv.push_back(uv0);
    m.triangles.push_back(t1), m.appearance.triangle_uv.push_back(uv1);
  }
  return m;
}

// Capture from six synthetic views of a box coloured by a known field recovers the field: on
// the surface points the views saw, the captured texture's colour (read back through the
// colour grid) is within 2 levels of the field on average and 6 at the 95th percentile (0.45
// and 1.0 when written).
TEST(Capture, RecoversAKnownColourFieldFromSyntheticViews) {
  const Mesh mesh = AtlasBox();
  ASSERT_TRUE(mesh.Validate("box").ok());
  std::vector<testing::SyntheticFrame> frames;
  std::vector<SE3> poses;
  for (int k = 0; k < 6; ++k) {
    const Eigen::Vector3d axis = Eigen::Vector3d(std::sin(k * 1.3), std::cos(k * 0.7), 0.5).normalized();
    poses.emplace_back(ExpSO3(axis * (0.6 + 0.9 * k)), Eigen::Vector3d(0.01 * (k % 3 - 1), 0.0, 0.5));
    frames.push_back(testing::RenderFrame(mesh, poses.back(), Field, k));
  }
  std::vector<PosedView> views;
  for (int k = 0; k < 6; ++k)
    views.push_back({frames[k].K, &frames[k].depth, &frames[k].colour, &frames[k].visible, poses[k]});
  CaptureOptions options;
  options.texture_size = 256;
  CaptureStats stats;
  auto captured = CaptureFromViews(mesh, views, options, &stats);
  ASSERT_TRUE(captured.ok()) << captured.status().ToString();
  ASSERT_TRUE(captured->has_texture());
  EXPECT_EQ(stats.views, 6);
  EXPECT_GT(stats.known, stats.points / 2);

  Mesh coloured = mesh;
  coloured.appearance = *captured;
  const auto grid = ColourGrid::Build(coloured);
  ASSERT_NE(grid, nullptr);
  // Surface points away from the edges (cells there mix two faces' colours).
  std::vector<double> errors;
  Rng rng(3, 3);
  const Eigen::Vector3f lo = mesh.BoundsMin(), hi = mesh.BoundsMax();
  for (int k = 0; k < 3000; ++k) {
    const int f = k % 6, a = f / 2, b = (a + 1) % 3, c = (a + 2) % 3;
    Eigen::Vector3f p;
    const float margin = 2 * grid->cell_m();
    p[a] = f % 2 ? hi[a] : lo[a];
    p[b] = static_cast<float>(rng.Uniform(lo[b] + margin, hi[b] - margin));
    p[c] = static_cast<float>(rng.Uniform(lo[c] + margin, hi[c] - margin));
    const Rgba8 got = grid->At(p);
    if (got.a == 0) continue;  // no view saw it
    const Rgba8 want = Field(p);
    errors.push_back((std::abs(got.r - want.r) + std::abs(got.g - want.g) + std::abs(got.b - want.b)) / 3.0);
  }
  ASSERT_GT(errors.size(), 1500u);
  std::sort(errors.begin(), errors.end());
  double mean = 0;
  for (double e : errors) mean += e;
  mean /= static_cast<double>(errors.size());
  std::printf("  capture error: mean %.2f, 95th percentile %.2f levels over %zu points\n", mean,
              errors[errors.size() * 95 / 100], errors.size());
  EXPECT_LT(mean, 2.0);
  EXPECT_LT(errors[errors.size() * 95 / 100], 6.0);
}

// Vertex mode (a mesh without a texture layout): each vertex a view saw gets the field's colour.
TEST(Capture, VertexColoursWithoutATextureLayout) {
  Mesh mesh = testing::Blob();
  const SE3 T(ExpSO3(Eigen::Vector3d(0.3, 0.2, 0.1)), Eigen::Vector3d(0, 0, 0.45));
  const testing::SyntheticFrame frame = testing::RenderFrame(mesh, T, Field, 1);
  const PosedView view{frame.K, &frame.depth, &frame.colour, &frame.visible, T};
  CaptureStats stats;
  auto captured = CaptureFromViews(mesh, std::span(&view, 1), CaptureOptions{}, &stats);
  ASSERT_TRUE(captured.ok());
  ASSERT_EQ(captured->vertex_colours.size(), mesh.vertices_m.size());
  int seen = 0;
  double error = 0;
  for (size_t v = 0; v < mesh.vertices_m.size(); ++v) {
    const Rgba8 c = captured->vertex_colours[v];
    if (c.a == 0) continue;
    ++seen;
    const Rgba8 want = Field(mesh.vertices_m[v]);
    error += (std::abs(c.r - want.r) + std::abs(c.g - want.g) + std::abs(c.b - want.b)) / 3.0;
  }
  EXPECT_GT(seen, static_cast<int>(mesh.vertices_m.size()) / 4);
  EXPECT_LT(seen, static_cast<int>(mesh.vertices_m.size()));  // the far side is unknown
  EXPECT_LT(error / seen, 6.0);
}

TEST(Capture, InconsistentViewsAndOptionsAreErrors) {
  const Mesh mesh = testing::Blob();
  const SE3 T(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 0.45));
  testing::SyntheticFrame frame = testing::RenderFrame(mesh, T, Field, 1);
  frame.colour.width = 100;
  const PosedView view{frame.K, &frame.depth, &frame.colour, &frame.visible, T};
  auto r = CaptureFromViews(mesh, std::span(&view, 1), CaptureOptions{}, nullptr);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("view 0"), std::string::npos);
  CaptureOptions bad;
  bad.texture_size = 3;
  EXPECT_FALSE(CaptureFromViews(mesh, {}, bad, nullptr).ok());
}

}  // namespace
}  // namespace mcpose::appearance

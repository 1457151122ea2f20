// Surface distances: the point-triangle distance on cases worked by hand, the grid search
// against every-triangle references on random meshes, and the measured LOD deviation.
#include "render/surface_distance.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "render/lod.h"
#include "synthetic_mesh.h"

namespace mcpose::render {
namespace {

using Vec3 = Eigen::Vector3f;

TEST(SurfaceDistance, PointTriangleOnHandWorkedCases) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_FLOAT_EQ(PointTriangleDistanceSquared(Vec3(0.25f, 0.25f, 2), a, b, c), 4.f);  // over the face
  EXPECT_FLOAT_EQ(PointTriangleDistanceSquared(Vec3(-1, -1, 0), a, b, c), 2.f);       // beyond vertex a
  EXPECT_FLOAT_EQ(PointTriangleDistanceSquared(Vec3(2, 0, 1), a, b, c), 2.f);         // beyond vertex b
  EXPECT_FLOAT_EQ(PointTriangleDistanceSquared(Vec3(0.5f, -3, 4), a, b, c), 25.f);    // beyond edge ab
  EXPECT_FLOAT_EQ(PointTriangleDistanceSquared(Vec3(1, 1, 0), a, b, c), 0.5f);        // beyond edge bc
  EXPECT_FLOAT_EQ(PointTriangleDistanceSquared(Vec3(-2, 0.5f, 0), a, b, c), 4.f);     // beyond edge ca
  // Degenerate: a segment from (0,0,0) to (2,0,0) (c in the middle), and a point.
  EXPECT_FLOAT_EQ(PointTriangleDistanceSquared(Vec3(1, 3, 0), a, Vec3(2, 0, 0), Vec3(1, 0, 0)), 9.f);
  EXPECT_FLOAT_EQ(PointTriangleDistanceSquared(Vec3(0, 3, 4), a, a, a), 25.f);
}

// n random triangles in a box of side `size` around the origin, some of them long and thin.
Mesh RandomSoup(std::mt19937& rng, int n, float size) {
  std::uniform_real_distribution<float> u(-0.5f * size, 0.5f * size);
  std::uniform_real_distribution<float> small(-0.05f * size, 0.05f * size);
  Mesh m;
  for (int i = 0; i < n; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const bool thin = i % 5 == 0;
    for (int k = 0; k < 3; ++k)
      m.vertices_m.push_back(thin && k == 2 ? Vec3(u(rng), u(rng), u(rng)) : p + Vec3(small(rng), small(rng), small(rng)));
    const uint32_t v = static_cast<uint32_t>(3 * i);
    m.triangles.push_back({v, v + 1, v + 2});
  }
  return m;
}

TEST(SurfaceDistance, GridSearchEqualsEveryTriangleOnRandomMeshes) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 40; ++trial) {
    const int n = 1 + trial * 13;
    const Mesh mesh = RandomSoup(rng, n, 0.2f);
    std::uniform_real_distribution<float> u(-0.3f, 0.3f);  // some points outside the grid
    std::vector<Vec3> points;
    for (int i = 0; i < 200; ++i) points.emplace_back(u(rng), u(rng), u(rng));
    EXPECT_FLOAT_EQ(MaxDistanceToSurface(points, mesh), MaxDistanceToSurfaceReference(points, mesh))
        << "trial " << trial << ", " << n << " triangles";
    const TriangleGrid grid(mesh);
    for (int i = 0; i < 20; ++i) {
      const Vec3& p = points[static_cast<size_t>(i)];
      const float reference = MaxDistanceToSurfaceReference(std::span(&p, 1), mesh);
      EXPECT_FLOAT_EQ(grid.Distance(p), reference);
      // The nearest triangle: its distance is the reference's, and the returned one.
      const TriangleGrid::Nearest hit = grid.NearestTriangle(p);
      ASSERT_LT(hit.triangle, mesh.triangles.size());
      const auto& t = mesh.triangles[hit.triangle];
      EXPECT_FLOAT_EQ(hit.distance, reference);
      EXPECT_FLOAT_EQ(std::sqrt(PointTriangleDistanceSquared(p, mesh.vertices_m[t[0]], mesh.vertices_m[t[1]],
                                                              mesh.vertices_m[t[2]])),
                      reference);
    }
  }
  // A flat mesh (zero extent in z) and an empty one.
  Mesh flat;
  flat.vertices_m = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  flat.triangles = {{0, 1, 2}};
  EXPECT_FLOAT_EQ(TriangleGrid(flat).Distance(Vec3(0.2f, 0.2f, -3)), 3.f);
  EXPECT_TRUE(std::isinf(TriangleGrid(Mesh{}).Distance(Vec3(0, 0, 0))));
  EXPECT_EQ(TriangleGrid(Mesh{}).NearestTriangle(Vec3(0, 0, 0)).triangle, UINT32_MAX);
}

// Two parallel unit squares facing +z (counter-clockwise seen from +z), 2 mm apart: the upper
// one lies in front of the lower one's faces (+2 mm), the lower one behind the upper's (-2 mm).
TEST(SurfaceDistance, SurfaceOffsetsAreSignedByTheNearestFace) {
  auto square = [](float z, float side) {
    Mesh m;
    m.vertices_m = {Vec3(0, 0, z), Vec3(side, 0, z), Vec3(side, side, z), Vec3(0, side, z)};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    return m;
  };
  const Mesh lower = square(0.f, 1.f), upper = square(0.002f, 1.f);
  for (const SurfaceOffset& o : SurfaceOffsets(upper, lower)) {
    EXPECT_FLOAT_EQ(o.signed_m, 0.002f);
    EXPECT_FLOAT_EQ(o.area_m2, 0.5f);
    EXPECT_LT(o.nearest_triangle, 2u);
  }
  const OffsetMeans below = MeanOffsets(SurfaceOffsets(lower, upper));
  EXPECT_NEAR(below.signed_m, -0.002, 1e-9);
  EXPECT_NEAR(below.abs_m, 0.002, 1e-9);
  // Weighted by area: against the upper square, a small square 2 mm in front of it (area 1/4)
  // and the lower one 2 mm behind (area 1) give (0.25 * 2 - 1 * 2) / 1.25 = -1.2 mm.
  Mesh both = lower;
  for (const Vec3& v : square(0.004f, 0.5f).vertices_m) both.vertices_m.push_back(v);
  both.triangles.push_back({4, 5, 6});
  both.triangles.push_back({4, 6, 7});
  const OffsetMeans mixed = MeanOffsets(SurfaceOffsets(both, upper));
  EXPECT_NEAR(mixed.signed_m, -0.0012, 1e-8);
  EXPECT_NEAR(mixed.abs_m, 0.002, 1e-8);
  EXPECT_TRUE(SurfaceOffsets(upper, Mesh{}).empty());
  // Every second full triangle: triangle 0 of the lower square only.
  const std::vector<SurfaceOffset> strided = SurfaceOffsets(lower, upper, 2);
  ASSERT_EQ(strided.size(), 1u);
  EXPECT_EQ(strided[0].full_triangle, 0u);
  EXPECT_FLOAT_EQ(strided[0].signed_m, -0.002f);
  // The signed distance alone: in front of the face, behind it, and beyond an edge.
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_FLOAT_EQ(SignedDistanceToTriangle(Vec3(0.25f, 0.25f, 2), a, b, c), 2.f);
  EXPECT_FLOAT_EQ(SignedDistanceToTriangle(Vec3(0.25f, 0.25f, -2), a, b, c), -2.f);
  EXPECT_FLOAT_EQ(SignedDistanceToTriangle(Vec3(0.5f, -3, -4), a, b, c), -5.f);
  EXPECT_FLOAT_EQ(SignedDistanceToTriangle(Vec3(0.25f, 0.25f, 2), a, c, b), -2.f);  // clockwise: faces -z
}

// A square of n x n quads in z = 0 whose centre vertex is raised by h, and the same square as
// two flat triangles: the two surfaces are h apart (at the raised vertex).
TEST(SurfaceDistance, DeviationOfAFlattenedBumpIsItsHeight) {
  const int n = 8;
  const float h = 0.003f;
  Mesh bumpy, flat;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      bumpy.vertices_m.emplace_back(0.01f * i, 0.01f * j, i == n / 2 && j == n / 2 ? h : 0.f);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t v = static_cast<uint32_t>(j * (n + 1) + i), w = v + n + 1;
      bumpy.triangles.push_back({v, v + 1, w + 1});
      bumpy.triangles.push_back({v, w + 1, w});
    }
  flat.vertices_m = {Vec3(0, 0, 0), Vec3(0.01f * n, 0, 0), Vec3(0.01f * n, 0.01f * n, 0), Vec3(0, 0.01f * n, 0)};
  flat.triangles = {{0, 1, 2}, {0, 2, 3}};
  const DeviationMeter meter(bumpy);
  EXPECT_FLOAT_EQ(meter.Measure(flat), h);
  EXPECT_FLOAT_EQ(SampledDeviationReferenceM(bumpy, flat), h);
  EXPECT_NEAR(meter.Measure(bumpy), 0.f, 1e-7f);  // centroids project back with rounding
}

// A closed blob with bumps (tests/synthetic_mesh.h), simplified by the LOD chain with
// meshoptimizer's vertices: every level's measured deviation equals the every-triangle
// reference, and error_m is at least it and meshoptimizer's figure.
TEST(SurfaceDistance, LodLevelsCarryTheirMeasuredDeviation) {
  const Mesh m = testing::Blob();
  const LodChain chain = LodChain::Build(m, LodVertices::kKept);
  ASSERT_GE(chain.num_levels(), 3);
  const DeviationMeter meter(m);
  for (int l = 1; l < chain.num_levels(); ++l) {
    const LodLevel& level = chain.level(l);
    const float measured = meter.Measure(level.mesh);
    EXPECT_FLOAT_EQ(measured, SampledDeviationReferenceM(m, level.mesh)) << "level " << l;
    EXPECT_GE(level.error_m, measured);
    EXPECT_GE(level.error_m, level.meshopt_error_m);
    EXPECT_GE(level.error_m, chain.level(l - 1).error_m);
    EXPECT_GT(measured, 0.f);
  }
}

// The same blob's chain with meshoptimizer's vertices (kKept) and unbiased ones: the same
// triangles and the same error_m (so the same level selection); kept vertices are the full mesh's, and their levels lie inside the bulging blob
// on average; the unbiased levels' mean signed offset is near zero and their mean distance
// smaller.
TEST(SurfaceDistance, UnbiasedLodLevelsLieOnTheFullSurfaceOnAverage) {
  const Mesh m = testing::Blob();
  const LodChain kept = LodChain::Build(m, LodVertices::kKept);
  const LodChain unbiased = LodChain::Build(m, LodVertices::kUnbiased);
  ASSERT_EQ(kept.num_levels(), unbiased.num_levels());
  ASSERT_GE(kept.num_levels(), 3);
  int coarse = 0;
  for (int l = 1; l < kept.num_levels(); ++l) {
    const Mesh &k = kept.level(l).mesh, &u = unbiased.level(l).mesh;
    ASSERT_EQ(k.triangles, u.triangles) << "level " << l;
    for (const Vec3& v : k.vertices_m)
      EXPECT_NE(std::find(m.vertices_m.begin(), m.vertices_m.end(), v), m.vertices_m.end());
    EXPECT_EQ(unbiased.level(l).error_m, kept.level(l).error_m) << "level " << l;  // the same selection
    // The levels that stray 0.1 mm or more on average (on this 10 cm blob, levels 3-6 of 515
    // to 89 triangles: 0.3-3.7 mm inside before, within 0.05 mm after; the mean distance about
    // halved).
    const OffsetMeans before = MeanOffsets(SurfaceOffsets(m, k)), after = MeanOffsets(SurfaceOffsets(m, u));
    if (before.abs_m < 1e-4) continue;
    ++coarse;
    EXPECT_GT(before.signed_m, 0.5 * before.abs_m) << "level " << l;  // inside on average
    EXPECT_LT(std::fabs(after.signed_m), 0.05 * before.signed_m) << "level " << l;
    EXPECT_LT(after.abs_m, 0.6 * before.abs_m) << "level " << l;
  }
  EXPECT_GE(coarse, 3);
}

}  // namespace
}  // namespace mcpose::render

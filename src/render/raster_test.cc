#include "render/raster.h"
#include "render/raster_fixed.h"
#include "mcpose/simd.h"
#include "mcpose/option_table.h"
#include "core/parallel_for.h"
#include "render/simd_dispatch.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <thread>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <hwy/targets.h>

#include "raster_test_util.h"

namespace mcpose::render {
namespace {

struct Scene {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<std::array<uint32_t, 3>> triangles;
};

// Random triangles in front of the camera, a few pixels to a few dozen pixels across.
Scene RandomScene(std::mt19937_64& gen, int n) {
  std::uniform_real_distribution<float> xy(-0.12f, 0.12f), z(0.5f, 1.2f), d(-0.02f, 0.02f);
  Scene s;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3f c(xy(gen), xy(gen), z(gen));
    for (int k = 0; k < 3; ++k) s.vertices.push_back(c + Eigen::Vector3f(d(gen), d(gen), d(gen)));
    s.triangles.push_back({uint32_t(3 * i), uint32_t(3 * i + 1), uint32_t(3 * i + 2)});
  }
  return s;
}

// Brute force: for every pixel, intersect its viewing ray with every triangle in double
// precision (pixel centre at integer coordinates). Returns the nearest depth, or +inf.
// `ambiguous` marks pixels whose centre lies within `tol` (barycentric) of an edge.
void BruteForce(const Scene& s, const RasterParams& p, std::vector<float>* z,
                std::vector<char>* ambiguous) {
  const PixelRect& b = p.box;
  z->assign(b.area(), INFINITY);
  ambiguous->assign(b.area(), 0);
  for (int y = b.y0; y < b.y1; ++y) {
    for (int x = b.x0; x < b.x1; ++x) {
      const Eigen::Vector3d dir((x - p.cx) / p.fx, (y - p.cy) / p.fy, 1.0);
      const size_t idx = (y - b.y0) * b.width() + (x - b.x0);
      for (const auto& t : s.triangles) {
        const Eigen::Vector3d a = s.vertices[t[0]].cast<double>(), bb = s.vertices[t[1]].cast<double>(),
                              c = s.vertices[t[2]].cast<double>();
        const Eigen::Vector3d n = (bb - a).cross(c - a);
        const bool front = n.dot(a) < 0;
        if (p.cull_backfaces && !front) continue;
        const double denom = n.dot(dir);
        if (std::abs(denom) < 1e-15) continue;
        const double s_ray = n.dot(a) / denom;  // point = s_ray * dir, depth = s_ray
        const Eigen::Vector3d q = s_ray * dir;
        // Barycentric coordinates of q.
        const double area = n.norm();
        const double wa = (bb - q).cross(c - q).dot(n) / (area * area);
        const double wb = (c - q).cross(a - q).dot(n) / (area * area);
        const double wc = 1.0 - wa - wb;
        const double tol = 1e-4;
        if (std::min({wa, wb, wc}) > tol) {
          (*z)[idx] = std::min((*z)[idx], static_cast<float>(s_ray));
        } else if (std::min({wa, wb, wc}) > -tol) {
          (*ambiguous)[idx] = 1;
        }
      }
    }
  }
}

class RasterVsBruteForce : public ::testing::TestWithParam<bool> {};

TEST_P(RasterVsBruteForce, CoverageAndDepthMatchOnRandomTriangles) {
  const bool cull = GetParam();
  std::mt19937_64 gen(cull ? 11 : 12);
  for (int trial = 0; trial < 20; ++trial) {
    const Scene s = RandomScene(gen, 60);
    const RasterParams p = TestRasterParams(cull);
    std::vector<ScreenVertex> sv(s.vertices.size());
    ProjectVertices(s.vertices, Eigen::Matrix3f::Identity(), Eigen::Vector3f::Zero(), p, sv);
    std::vector<float> zbuf(p.box.area(), INFINITY);
    RasterCounters stats;
    RasterizeDepthReference(sv, s.triangles, p, zbuf.data(), &stats);

    std::vector<float> z_ref;
    std::vector<char> ambiguous;
    BruteForce(s, p, &z_ref, &ambiguous);
    int compared = 0, covered = 0;
    for (size_t i = 0; i < zbuf.size(); ++i) {
      if (ambiguous[i]) continue;
      ++compared;
      ASSERT_EQ(std::isinf(zbuf[i]), std::isinf(z_ref[i])) << "trial " << trial << " pixel " << i;
      if (!std::isinf(z_ref[i])) {
        ++covered;
        EXPECT_NEAR(zbuf[i], z_ref[i], 5e-5f * z_ref[i]);  // float edge functions
      }
    }
    EXPECT_GT(covered, 100);
    EXPECT_GT(compared, static_cast<int>(zbuf.size()) * 9 / 10);

    // Every triangle has exactly one fate.
    EXPECT_EQ(stats.triangles_in, 60);
    EXPECT_EQ(stats.culled_near + stats.culled_degenerate + stats.culled_backface +
                  stats.culled_outside_box + stats.culled_between_pixels + stats.triangles_rasterized,
              stats.triangles_in);
    if (!cull) {
      EXPECT_EQ(stats.culled_backface, 0);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Culling, RasterVsBruteForce, ::testing::Bool());

TEST(Raster, SharedEdgesCoverEachPixelOnce) {
  // A square split along its diagonal, pixel-aligned so many centres lie on the shared edges.
  Scene s;
  s.vertices = {{-0.05f, -0.05f, 1.f}, {0.05f, -0.05f, 1.f}, {0.05f, 0.05f, 1.f}, {-0.05f, 0.05f, 1.f}};
  // Counter-clockwise seen from the camera side (the normal points to -z).
  s.triangles = {{0, 2, 1}, {0, 3, 2}};
  RasterParams p = TestRasterParams(true);
  p.fx = p.fy = 1000.f;
  p.cx = 300.f, p.cy = 240.f;
  std::vector<ScreenVertex> sv(4);
  ProjectVertices(s.vertices, Eigen::Matrix3f::Identity(), Eigen::Vector3f::Zero(), p, sv);
  std::vector<float> zbuf(p.box.area(), INFINITY);
  RasterCounters stats;
  RasterizeDepthReference(sv, s.triangles, p, zbuf.data(), &stats);
  EXPECT_EQ(stats.triangles_rasterized, 2);
  // The square spans u, v in [250, 350] x [190, 290]: centres 250..349 (top-left rule) = 100 x 100.
  EXPECT_EQ(stats.fragments, 100 * 100);
}

TEST(Raster, BackfacesAreCulledAndNearPlaneTrianglesDropped) {
  Scene s;
  s.vertices = {{-0.05f, -0.05f, 1.f}, {0.05f, -0.05f, 1.f}, {0.05f, 0.05f, 1.f}, {0.f, 0.f, 0.01f}};
  s.triangles = {{0, 1, 2} /* back face */, {0, 2, 1} /* front */, {0, 1, 3} /* near */};
  RasterParams p = TestRasterParams(true);
  std::vector<ScreenVertex> sv(4);
  ProjectVertices(s.vertices, Eigen::Matrix3f::Identity(), Eigen::Vector3f::Zero(), p, sv);
  std::vector<float> zbuf(p.box.area(), INFINITY);
  RasterCounters stats;
  RasterizeDepthReference(sv, s.triangles, p, zbuf.data(), &stats);
  EXPECT_EQ(stats.culled_backface, 1);
  EXPECT_EQ(stats.culled_near, 1);
  EXPECT_EQ(stats.triangles_rasterized, 1);
}


// The fixed-point core against the float reference on random triangles: identical culling of
// whole triangles except near-degenerate ones, coverage equal except for pixel centres within
// a sub-pixel step of an edge, depth equal to float precision.
class FixedVsReference : public ::testing::TestWithParam<bool> {};

TEST_P(FixedVsReference, CoverageAndDepthAgreeOnRandomTriangles) {
  const bool cull = GetParam();
  std::mt19937_64 gen(cull ? 31 : 32);
  int64_t pixels = 0, differ = 0;
  for (int trial = 0; trial < 30; ++trial) {
    const Scene s = RandomScene(gen, 80);
    const RasterParams p = TestRasterParams(cull);
    std::vector<ScreenVertex> sv(s.vertices.size());
    ProjectVertices(s.vertices, Eigen::Matrix3f::Identity(), Eigen::Vector3f::Zero(), p, sv);
    std::vector<float> z_ref(p.box.area(), INFINITY), z_fix(p.box.area(), INFINITY);
    RasterCounters st_ref, st_fix;
    RasterizeDepthReference(sv, s.triangles, p, z_ref.data(), &st_ref);
    RasterizeDepthFixedPoint(sv, s.triangles, p, z_fix.data(), &st_fix);
    EXPECT_EQ(st_fix.triangles_in, st_ref.triangles_in);
    EXPECT_EQ(st_fix.culled_backface, st_ref.culled_backface);
    EXPECT_EQ(st_fix.culled_near + st_fix.culled_degenerate + st_fix.culled_backface +
                  st_fix.culled_outside_box + st_fix.culled_between_pixels + st_fix.triangles_rasterized,
              st_fix.triangles_in);
    for (size_t i = 0; i < z_ref.size(); ++i) {
      if (std::isinf(z_ref[i]) && std::isinf(z_fix[i])) continue;
      ++pixels;
      // A flip: covered by one and not the other, or (overlapping triangles) a different
      // triangle nearest. Otherwise the depth agrees: snapping moves vertices by <= 1/32 px,
      // under 0.2 mm on these 1-6 cm triangles.
      if (std::isinf(z_ref[i]) != std::isinf(z_fix[i]) || std::fabs(z_fix[i] - z_ref[i]) > 2e-4f) ++differ;
    }
  }
  EXPECT_GT(pixels, 10000);
  // Only pixel centres within ~1/32 px of an edge can flip.
  EXPECT_LT(static_cast<double>(differ) / pixels, 0.01) << differ << " of " << pixels;
}

INSTANTIATE_TEST_SUITE_P(Culling, FixedVsReference, ::testing::Bool());

// The fixed-point setup's 1/z plane (float) against 1/z interpolated in double over the same
// snapped vertices, at every pixel centre the edge functions cover: thin slivers and triangles
// far from the box corner (where the plane's C extrapolates furthest) included. Measured
// with the float setup: mean relative error 1.8e-6, worst 4.2e-4 (0.4 mm at 1 m), 600 pixels
// from the corner of a 640 x 480 box; the plane computed in double and rounded to float gave
// 0.7e-6 and 3.6e-4 on the same pixels (its evaluation in float dominates the worst case).
TEST(RasterFixed, FloatDepthPlaneMatchesDoubleInterpolation) {
  std::mt19937_64 gen(33);
  RasterParams p;
  p.box = PixelRect{0, 0, 640, 480};
  p.cull_backfaces = false;  // these triangles face away: the setup reorders them
  std::uniform_real_distribution<float> pos(0.f, 640.f), size(0.5f, 40.f), z(0.3f, 2.0f), thin(0.01f, 0.3f);
  std::uniform_real_distribution<float> angle(0.f, 6.2831853f);
  double worst = 0, sum = 0;
  int64_t pixels = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    // A triangle of random size or a sliver (one side much shorter than the others), anywhere.
    const float cx = pos(gen), cy = pos(gen) * 0.75f, len = size(gen), a = angle(gen);
    const float w = trial % 2 ? len * thin(gen) : size(gen);
    const ScreenVertex v0{cx, cy, z(gen)};
    const ScreenVertex v1{cx + len * std::cos(a), cy + len * std::sin(a), z(gen)};
    const ScreenVertex v2{cx + w * std::cos(a + 1.5707963f), cy + w * std::sin(a + 1.5707963f), z(gen)};
    FixedTriangle t;
    if (SetupFixedTriangle(v0, v1, v2, p, &t) != TriangleSetup::kReady) continue;
    // The snapped vertices, as the setup snaps them.
    const ScreenVertex* v[3] = {&v0, &v1, &v2};
    int64_t X[3], Y[3];
    for (int k = 0; k < 3; ++k) X[k] = std::lrint(v[k]->u * kSubpixelOne), Y[k] = std::lrint(v[k]->v * kSubpixelOne);
    const double area = double((X[1] - X[0]) * (Y[2] - Y[0]) - (Y[1] - Y[0]) * (X[2] - X[0]));
    int64_t w_row[3] = {t.w_row[0], t.w_row[1], t.w_row[2]};
    for (int32_t y = t.y_lo; y <= t.y_hi; ++y) {
      int64_t e[3] = {w_row[0], w_row[1], w_row[2]};
      for (int32_t x = t.x_lo; x <= t.x_hi; ++x) {
        if ((e[0] | e[1] | e[2]) >= 0) {
          // Barycentric weights of the snapped triangle at the pixel centre, in double.
          const int64_t px = int64_t{x} * kSubpixelOne, py = int64_t{y} * kSubpixelOne;
          double inv_z = 0;
          for (int k = 0; k < 3; ++k) {
            const int b = (k + 1) % 3, c = (k + 2) % 3;  // edge b -> c, opposite vertex k
            const double ek = double((X[c] - X[b]) * (py - Y[b]) - (Y[c] - Y[b]) * (px - X[b]));
            inv_z += ek / area / v[k]->z;
          }
          const float z_plane = 1.0f / (t.A * static_cast<float>(x) + (t.B * static_cast<float>(y) + t.C));
          const double rel = std::fabs(z_plane * inv_z - 1.0);
          worst = std::max(worst, rel);
          sum += rel;
          ++pixels;
          ASSERT_LT(rel, 1e-3) << "trial " << trial << " pixel " << x << ", " << y;
        }
        for (int k = 0; k < 3; ++k) e[k] += t.step_x[k];
      }
      for (int k = 0; k < 3; ++k) w_row[k] += t.step_y[k];
    }
  }
  EXPECT_GT(pixels, 100000);
  EXPECT_LT(sum / pixels, 5e-6);
  std::printf("float depth plane: relative depth error mean %.3g, worst %.3g over %lld pixels\n", sum / pixels,
              worst, static_cast<long long>(pixels));
}

TEST(RasterFixed, HugeAndOffscreenTrianglesFallBackToFloatPath) {
  // One triangle far larger than the integer range and partly behind the box: the result must
  // equal the reference exactly, since both take the float path.
  Scene s;
  s.vertices = {{-50.f, -50.f, 1.f}, {50.f, 50.f, 1.f}, {50.f, -50.f, 1.f}};
  s.triangles = {{0, 1, 2}};
  const RasterParams p = TestRasterParams(false);
  std::vector<ScreenVertex> sv(3);
  ProjectVertices(s.vertices, Eigen::Matrix3f::Identity(), Eigen::Vector3f::Zero(), p, sv);
  std::vector<float> z_ref(p.box.area(), INFINITY), z_fix(p.box.area(), INFINITY);
  RasterCounters a, b;
  RasterizeDepthReference(sv, s.triangles, p, z_ref.data(), &a);
  RasterizeDepthFixedPoint(sv, s.triangles, p, z_fix.data(), &b);
  EXPECT_EQ(z_ref, z_fix);
  EXPECT_EQ(a.fragments, b.fragments);
  EXPECT_EQ(b.triangles_in, 1);
}


// Both rasterizers write only inside CoverBound: a z-buffer pre-filled with a sentinel keeps
// it everywhere outside the rect.
TEST(Raster, CoverBoundHoldsEveryWrittenPixel) {
  std::mt19937_64 gen(41);
  for (int trial = 0; trial < 40; ++trial) {
    // A few triangles, so the bound is often much smaller than the box.
    const Scene s = RandomScene(gen, 1 + trial % 4);
    RasterParams p = TestRasterParams(trial % 2 == 0);
    std::vector<ScreenVertex> sv(s.vertices.size());
    ProjectVertices(s.vertices, Eigen::Matrix3f::Identity(), Eigen::Vector3f::Zero(), p, sv);
    const PixelRect r = CoverBound(sv, p.box);
    for (int fixed = 0; fixed < 2; ++fixed) {
      std::vector<float> z(p.box.area(), -1.f);
      if (fixed) {
        RasterizeDepthFixedPoint(sv, s.triangles, p, z.data(), nullptr);
      } else {
        // The reference compares with what is there; +inf inside the rect lets it write.
        for (int y = r.y0; y < r.y1; ++y)
          for (int x = r.x0; x < r.x1; ++x) z[(y - p.box.y0) * p.box.width() + (x - p.box.x0)] = INFINITY;
        RasterizeDepthReference(sv, s.triangles, p, z.data(), nullptr);
      }
      for (int y = p.box.y0; y < p.box.y1; ++y)
        for (int x = p.box.x0; x < p.box.x1; ++x) {
          const bool inside = x >= r.x0 && x < r.x1 && y >= r.y0 && y < r.y1;
          if (!inside) { ASSERT_EQ(z[(y - p.box.y0) * p.box.width() + (x - p.box.x0)], -1.f) << x << "," << y; }
        }
    }
  }
  // No vertices, or all far outside: empty.
  EXPECT_TRUE(CoverBound({}, TestRasterParams(true).box).empty());
  const ScreenVertex far[3] = {{-500, -500, 1}, {-400, -500, 1}, {-500, -400, 1}};
  EXPECT_TRUE(CoverBound(far, TestRasterParams(true).box).empty());
  const ScreenVertex nan[1] = {{NAN, 0, 1}};
  EXPECT_EQ(CoverBound(nan, TestRasterParams(true).box).area(), TestRasterParams(true).box.area());
  // Vertices near the camera plane project past the range of int: the box on their side.
  const PixelRect box = TestRasterParams(true).box;
  const ScreenVertex huge[3] = {{-1e30f, 210, 1}, {1e30f, 1e30f, 1}, {300, -1e20f, 1}};
  const PixelRect all = CoverBound(huge, box);
  EXPECT_TRUE(all.x0 == box.x0 && all.x1 == box.x1 && all.y0 == box.y0 && all.y1 == box.y1);
  const ScreenVertex one_side[3] = {{250.5f, 200.5f, 1}, {1e30f, 250, 1}, {260, 260.5f, 1}};
  const PixelRect right = CoverBound(one_side, box);
  EXPECT_TRUE(right.x0 == 249 && right.x1 == box.x1 && right.y0 == 199 && right.y1 == 263)
      << right.x0 << " " << right.x1 << " " << right.y0 << " " << right.y1;
}


// The Highway row kernel against the scalar one on every compiled target this CPU supports:
// bit-identical z-buffers and statistics on random triangles, small and large.
TEST(RasterSimd, BitIdenticalToScalarRowsOnEveryTarget) {
  const std::vector<int64_t> targets = hwy::SupportedAndGeneratedTargets();
  ASSERT_FALSE(targets.empty());
  std::printf("  targets: %s\n", SimdTargetsAvailable().c_str());
  for (int64_t target : targets) {
    hwy::SetSupportedTargetsForTest(target);
    std::mt19937_64 gen(51);
    for (int trial = 0; trial < 30; ++trial) {
      Scene s = RandomScene(gen, 60);
      if (trial % 5 == 0) {  // one large triangle (hundreds of pixels) among the small ones
        s.vertices.push_back({-0.2f, -0.15f, 0.9f});
        s.vertices.push_back({-0.1f, 0.18f, 1.0f});
        s.vertices.push_back({0.25f, 0.0f, 0.8f});
        const uint32_t n = static_cast<uint32_t>(s.vertices.size());
        s.triangles.push_back({n - 3, n - 2, n - 1});
        s.triangles.push_back({n - 3, n - 1, n - 2});
      }
      const RasterParams p = TestRasterParams(trial % 2 == 0);
      std::vector<ScreenVertex> sv(s.vertices.size());
      ProjectVertices(s.vertices, Eigen::Matrix3f::Identity(), Eigen::Vector3f::Zero(), p, sv);
      std::vector<float> z_scalar(p.box.area(), INFINITY), z_simd(p.box.area() + kSimdPadFloats, INFINITY);
      RasterCounters st_scalar, st_simd;
      RasterizeDepthFixedPoint(sv, s.triangles, p, z_scalar.data(), &st_scalar, RowKernel::kScalar);
      RasterizeDepthFixedPoint(sv, s.triangles, p, z_simd.data(), &st_simd, RowKernel::kSimd);
      EXPECT_EQ(st_simd.fragments, st_scalar.fragments) << hwy::TargetName(target);
      EXPECT_EQ(st_simd.triangles_rasterized, st_scalar.triangles_rasterized) << hwy::TargetName(target);
      EXPECT_EQ(st_simd.culled_between_pixels, st_scalar.culled_between_pixels);
      ASSERT_EQ(0, std::memcmp(z_scalar.data(), z_simd.data(), z_scalar.size() * sizeof(float)))
          << hwy::TargetName(target) << " trial " << trial;
      for (size_t i = z_scalar.size(); i < z_simd.size(); ++i) ASSERT_EQ(z_simd[i], INFINITY) << "slack changed";
    }
  }
  hwy::SetSupportedTargetsForTest(0);
}

// The front face of triangle a, b, c set up in p's box; false when it is not ready
// (degenerate, or between pixel centres).
bool SetUpFrontFace(const ScreenVertex& a, const ScreenVertex& b, const ScreenVertex& c, const RasterParams& p,
                    FixedTriangle* ft) {
  TriangleSetup setup = SetupFixedTriangle(a, b, c, p, ft);
  if (setup == TriangleSetup::kCulledBackface) setup = SetupFixedTriangle(a, c, b, p, ft);
  return setup == TriangleSetup::kReady;
}

// `ft` filled into copies of `background` by the scalar rows and by the SIMD rows.
struct BothFills {
  int64_t n_scalar = 0, n_simd = 0;  // covered pixels
  std::vector<float> z_scalar, z_simd;
  bool same_bits = false;  // the z-buffers, bit for bit
};
BothFills FillBoth(const FixedTriangle& ft, const std::vector<float>& background, int stride) {
  BothFills f;
  f.z_scalar = background, f.z_simd = background;
  f.n_scalar = FillTriangleScalar(ft, f.z_scalar.data(), stride);
  f.n_simd = FillTriangleSimd(ft, f.z_simd.data(), stride);
  f.same_bits = std::memcmp(f.z_scalar.data(), f.z_simd.data(), background.size() * sizeof(float)) == 0;
  return f;
}

// Narrow triangles (1 to 70 pixels wide, 1 to 12 rows) take the blocks of rows (4 and 8
// pixels wide), the unrolled rows of 1 to 4 vectors and, past those, the row kernel:
// bit-identical to the scalar rows on every target, at every sub-pixel offset tried, over a
// z-buffer of random depths (so the depth test decides), and at the box's last rows and columns
// (where a block's rows past the triangle alias its last row).
TEST(RasterSimd, NarrowTrianglesBitIdenticalOnEveryTarget) {
  const RasterParams p = TestRasterParams(true);
  const float bw = static_cast<float>(p.box.width()), bh = static_cast<float>(p.box.height());
  std::mt19937_64 gen(5);
  std::uniform_real_distribution<float> frac(0.f, 1.f);
  for (int64_t target : hwy::SupportedAndGeneratedTargets()) {
    hwy::SetSupportedTargetsForTest(target);
    int filled = 0, kept_old = 0;
    std::vector<float> background(p.box.area() + kSimdPadFloats, INFINITY);
    std::uniform_real_distribution<float> depth(0.75f, 0.95f);
    for (size_t i = 0; i < static_cast<size_t>(p.box.area()); ++i) background[i] = depth(gen);
    for (int width = 1; width <= 70; width += width < 24 ? 1 : 3) {
      for (int trial = 0; trial < 30; ++trial) {
        const float height = 1.f + 11.f * frac(gen);
        // Inside the box, or against its right and bottom edges (clipped there).
        const float u0 = trial % 3 == 1 ? p.box.x0 + bw - width * frac(gen) - 1.f : 250.f + frac(gen);
        const float v0 = trial % 3 == 2 ? p.box.y0 + bh - height * frac(gen) - 1.f : 200.f + frac(gen);
        const ScreenVertex a{u0, v0, 0.8f}, b{u0 + width * frac(gen), v0 + height, 0.9f},
            c{u0 + static_cast<float>(width), v0 + height * frac(gen) - 1.f, 0.85f};
        FixedTriangle ft;
        if (!SetUpFrontFace(a, b, c, p, &ft)) continue;
        const BothFills f = FillBoth(ft, background, p.box.width());
        ASSERT_EQ(f.n_simd, f.n_scalar) << hwy::TargetName(target) << " width " << width;
        ASSERT_TRUE(f.same_bits) << hwy::TargetName(target) << " width " << width << " trial " << trial;
        filled += f.n_scalar > 0;
        int64_t changed = 0;
        for (size_t i = 0; i < background.size(); ++i) changed += f.z_scalar[i] != background[i];
        kept_old += f.n_scalar > changed;  // some covered pixels were behind the old depth
      }
    }
    EXPECT_GT(filled, 400) << hwy::TargetName(target);
    EXPECT_GT(kept_old, 100) << hwy::TargetName(target) << ": the depth test should keep some old depths";
  }
  hwy::SetSupportedTargetsForTest(0);
}

// Boxes narrower than a block (1 to 17 pixels wide): a block row's lanes past the triangle run
// on into the next row of the z-buffer, which may be a later row of the same vector. Bit-identical
// to the scalar rows on every target, over random depths.
TEST(RasterSimd, BoxesNarrowerThanABlockBitIdenticalOnEveryTarget) {
  std::mt19937_64 gen(17);
  std::uniform_real_distribution<float> frac(0.f, 1.f), depth(0.75f, 0.95f);
  for (int64_t target : hwy::SupportedAndGeneratedTargets()) {
    hwy::SetSupportedTargetsForTest(target);
    int filled = 0;
    for (int box_width = 1; box_width <= 17; ++box_width) {
      RasterParams p = TestRasterParams(true);
      p.box = PixelRect{300, 200, 300 + box_width, 230};
      std::vector<float> background(p.box.area() + kSimdPadFloats, INFINITY);
      for (size_t i = 0; i < static_cast<size_t>(p.box.area()); ++i) background[i] = depth(gen);
      for (int trial = 0; trial < 200; ++trial) {
        // Triangles about as wide as the box or wider (clipped to it), up to 30 rows tall.
        const float w = (box_width + 4) * frac(gen), h = 1.f + 29.f * frac(gen);
        const float u0 = p.box.x0 - 2.f + (box_width + 2) * frac(gen), v0 = p.box.y0 - 1.f + 10.f * frac(gen);
        const ScreenVertex a{u0, v0, 0.8f}, b{u0 + w * frac(gen), v0 + h, 0.9f},
            c{u0 + w, v0 + h * frac(gen), 0.85f};
        FixedTriangle ft;
        if (!SetUpFrontFace(a, b, c, p, &ft)) continue;
        const BothFills f = FillBoth(ft, background, p.box.width());
        ASSERT_EQ(f.n_simd, f.n_scalar) << hwy::TargetName(target) << " box width " << box_width;
        ASSERT_TRUE(f.same_bits) << hwy::TargetName(target) << " box width " << box_width << " trial " << trial;
        filled += f.n_scalar > 0;
      }
    }
    EXPECT_GT(filled, 1000) << hwy::TargetName(target);
  }
  hwy::SetSupportedTargetsForTest(0);
}

// The SIMD vertex stage against the scalar one on every target: random rotations, translations
// and vertex counts (whole vectors and tails), bit-identical screen vertices and cover rects,
// also with a vertex at the camera centre (infinite u, v: the whole box) and none at all; and
// the fused projection, snap and bound pass against the three.
TEST(ProjectSimd, BitIdenticalToScalarOnEveryTarget) {
  std::mt19937_64 gen(17);
  std::uniform_real_distribution<float> coord(-0.1f, 0.1f), angle(-3.f, 3.f);
  const RasterParams p = TestRasterParams(true);
  for (int64_t target : hwy::SupportedAndGeneratedTargets()) {
    hwy::SetSupportedTargetsForTest(target);
    for (int trial = 0; trial < 60; ++trial) {
      std::vector<Eigen::Vector3f> v(static_cast<size_t>(trial * 7 % 83));
      for (auto& x : v) x = Eigen::Vector3f(coord(gen), coord(gen), coord(gen));
      const Eigen::Matrix3f R =
          Eigen::AngleAxisf(angle(gen), Eigen::Vector3f(coord(gen), coord(gen), 1.f).normalized()).toRotationMatrix();
      Eigen::Vector3f t(coord(gen), coord(gen), 0.6f + coord(gen));
      if (trial % 10 == 9 && !v.empty()) t = -(R * v[v.size() / 2]);  // a vertex at the camera centre
      if (trial % 10 == 4) t.z() = p.z_near_m;  // vertices on both sides of the near plane
      if (trial % 10 == 6) t.x() = 1.3f;        // vertices beyond the snap band (u ~ 2300 px off)
      std::vector<ScreenVertex> a(v.size()), b(v.size());
      ProjectVertices(v, R, t, p, a);
      ProjectVerticesSimd(v, R, t, p, b);
      ASSERT_TRUE(a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(ScreenVertex)) == 0)
          << hwy::TargetName(target) << " trial " << trial;
      const PixelRect ra = CoverBound(a, p.box), rb = CoverBoundSimd(a, p.box);
      EXPECT_TRUE(ra.x0 == rb.x0 && ra.y0 == rb.y0 && ra.x1 == rb.x1 && ra.y1 == rb.y1)
          << hwy::TargetName(target) << " trial " << trial;
      if (trial % 10 == 9 && !v.empty()) {
        EXPECT_EQ(rb.area(), p.box.area()) << "not finite: the whole box";
      }
      // The fused pass: the same vertices, SnapVertexScalar's packed values, the same rect.
      std::vector<ScreenVertex> c(v.size());
      SnappedVertices snapped;
      const PixelRect rc = ProjectSnapBoundSimd(v, R, t, p, c, &snapped);
      ASSERT_TRUE(a.empty() || std::memcmp(a.data(), c.data(), a.size() * sizeof(ScreenVertex)) == 0)
          << hwy::TargetName(target) << " trial " << trial;
      ASSERT_EQ(snapped.packed.size(), v.size());
      for (size_t i = 0; i < v.size(); ++i) {
        ASSERT_EQ(snapped.packed[i], SnapVertexScalar(a[i], static_cast<float>(p.box.x0),
                                                      static_cast<float>(p.box.y0), p.z_near_m))
            << hwy::TargetName(target) << " trial " << trial << " vertex " << i;
      }
      EXPECT_TRUE(ra.x0 == rc.x0 && ra.y0 == rc.y0 && ra.x1 == rc.x1 && ra.y1 == rc.y1)
          << hwy::TargetName(target) << " trial " << trial;
    }
  }
  hwy::SetSupportedTargetsForTest(0);
}

// ClearDepthRectSimd on every target: exactly the rect's pixels become +infinity, for rects
// narrower than a vector, as wide as one, wider, and the whole buffer.
TEST(RasterSimd, ClearDepthRectSetsExactlyTheRect) {
  const int w = 70, h = 9;
  std::mt19937_64 gen(23);
  std::uniform_int_distribution<int> xs(0, w), ys(0, h);
  for (int64_t target : hwy::SupportedAndGeneratedTargets()) {
    hwy::SetSupportedTargetsForTest(target);
    for (int trial = 0; trial < 200; ++trial) {
      int x0 = xs(gen), x1 = xs(gen), y0 = ys(gen), y1 = ys(gen);
      if (trial == 0) x0 = 0, x1 = w, y0 = 0, y1 = h;
      if (trial == 1) x0 = 3, x1 = 3 + 16, y0 = 1, y1 = 2;
      if (x0 > x1) std::swap(x0, x1);
      if (y0 > y1) std::swap(y0, y1);
      std::vector<float> z(static_cast<size_t>(w) * h + kSimdPadFloats);
      for (size_t i = 0; i < z.size(); ++i) z[i] = static_cast<float>(i);
      ClearDepthRectSimd(z.data(), w, PixelRect{x0, y0, x1, y1});
      for (size_t i = 0; i < z.size(); ++i) {
        const int x = static_cast<int>(i % w), y = static_cast<int>(i / w);
        const bool inside = x >= x0 && x < x1 && y >= y0 && y < y1;
        ASSERT_EQ(z[i], inside ? INFINITY : static_cast<float>(i))
            << hwy::TargetName(target) << " rect " << x0 << "," << y0 << "-" << x1 << "," << y1 << " pixel " << i;
      }
    }
  }
  hwy::SetSupportedTargetsForTest(0);
}

// --simd-target: each thread dispatches to the target it was given, whatever the others do; the
// threads of a pool with that target's scope (an estimator's) all do.
TEST(SimdTargets, EachThreadDispatchesToItsOwnTarget) {
  const std::vector<int64_t> targets = hwy::SupportedAndGeneratedTargets();
  ASSERT_FALSE(targets.empty());
  const std::string best = hwy::TargetName(targets.front());
  EXPECT_EQ(DispatchedSimdTarget(), best);
  EXPECT_EQ(ThreadSimdTarget(), best);
  const auto names = SimdTargetNames();
  for (int64_t target : targets) {
    const std::string name = hwy::TargetName(target);
    int index = 0;
    for (size_t i = 1; i < names.size(); ++i)
      if (name == names[i]) index = static_cast<int>(i);
    ASSERT_GT(index, 0) << name;
    EXPECT_TRUE(SimdTargetSupported(index)) << name;
    EXPECT_EQ(DispatchedSimdTarget(static_cast<SimdTarget>(index)), name);
    std::string inside, beside;
    {
      const ThreadDispatchScope scope(CappedDispatchTarget(index));
      inside = ThreadSimdTarget();
      std::thread other([&] { beside = ThreadSimdTarget(); });
      other.join();
      // A pool whose threads enter the scope: every chunk, the caller's included, runs there.
      const hwy::ChosenTarget* capped = CappedDispatchTarget(index);
      ThreadPool pool(3, {[capped] { PushThreadDispatchTarget(capped); }, [] { PopThreadDispatchTarget(); }});
      std::vector<std::string> got(64);
      pool.ParallelFor(64, [&](int64_t b, int64_t e, int) {
        for (int64_t i = b; i < e; ++i) got[static_cast<size_t>(i)] = ThreadSimdTarget();
      });
      for (const std::string& g : got) EXPECT_EQ(g, name);
    }
    EXPECT_EQ(inside, name);
    EXPECT_EQ(beside, best);  // the other thread kept the process's
    EXPECT_EQ(ThreadSimdTarget(), best);  // the scope ended
  }
  EXPECT_FALSE(SimdTargetSupported(static_cast<int>(names.size())));
  EXPECT_EQ(CappedDispatchTarget(0), nullptr);  // best: the process's
}

}  // namespace
}  // namespace mcpose::render

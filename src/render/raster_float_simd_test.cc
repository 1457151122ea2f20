// RasterizeDepthFloatSimd against RasterizeDepthReference on every compiled target this CPU
// supports: bit-identical z-buffers and statistics.
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include "render/raster.h"
#include "render/raster_fixed.h"
#include "raster_test_util.h"

namespace mcpose::render {
namespace {

// Screen-space vertices meant to hit the reference's every branch: coordinates on a quarter-
// pixel grid (edge functions exactly zero at pixel centres, so the top-left rule decides),
// arbitrary floats, vertices far outside the box and near the camera plane, repeated and
// collinear vertices, and now and then an infinite or NaN coordinate or depth.
std::vector<ScreenVertex> RandomVertices(std::mt19937_64& gen, const PixelRect& box, int n) {
  std::uniform_real_distribution<float> unit(0.f, 1.f), depth(0.5f, 1.5f);
  std::uniform_int_distribution<int> kind(0, 99);
  std::vector<ScreenVertex> v;
  for (int i = 0; i < n; ++i) {
    // Centred on a random point of the box (and a margin around it), 0.3 to 40 pixels away.
    const float cu = box.x0 - 8 + (box.width() + 16) * unit(gen), cv = box.y0 - 8 + (box.height() + 16) * unit(gen);
    const float r = 0.3f + 40.f * unit(gen) * unit(gen);
    ScreenVertex p{cu + r * (2 * unit(gen) - 1), cv + r * (2 * unit(gen) - 1), depth(gen)};
    const int k = kind(gen);
    if (k < 35) {  // on the quarter-pixel grid
      p.u = std::round(p.u * 4) / 4, p.v = std::round(p.v * 4) / 4;
    } else if (k < 38) {
      p.z = 0.01f;  // in front of the near plane
    } else if (k < 40) {
      p.u = (k == 38 ? 1e30f : -3e4f);  // far off to a side
    } else if (k == 40) {
      p.v = INFINITY;
    } else if (k == 41) {
      p.u = NAN;
    } else if (k == 42) {
      p.z = NAN;
    } else if (k < 46 && i > 0) {
      p = v[static_cast<size_t>(i - 1)];  // repeated: a degenerate triangle
    }
    v.push_back(p);
  }
  return v;
}

std::vector<std::array<uint32_t, 3>> RandomTriangles(std::mt19937_64& gen, size_t n_vertices, int n) {
  std::uniform_int_distribution<uint32_t> pick(0, static_cast<uint32_t>(n_vertices - 1));
  std::vector<std::array<uint32_t, 3>> t;
  for (int i = 0; i < n; ++i) {
    // Mostly neighbours (small triangles, shared vertices), some spanning the pool.
    const uint32_t a = pick(gen);
    if (i % 4 == 0) {
      t.push_back({a, pick(gen), pick(gen)});
    } else {
      const uint32_t m = static_cast<uint32_t>(n_vertices);
      t.push_back({a, (a + 1) % m, (a + 2) % m});
    }
  }
  return t;
}

TEST(RasterFloatSimd, BitIdenticalToTheReferenceOnEveryTarget) {
  const std::vector<int64_t> targets = hwy::SupportedAndGeneratedTargets();
  ASSERT_FALSE(targets.empty());
  const PixelRect boxes[] = {{200, 150, 420, 330}, {0, 0, 37, 29}, {600, 440, 640, 480}, {300, 200, 301, 260},
                             {310, 200, 340, 201}, {250, 250, 250, 260}};
  for (int64_t target : targets) {
    hwy::SetSupportedTargetsForTest(target);
    std::mt19937_64 gen(17);
    std::uniform_real_distribution<float> background(0.6f, 1.4f);
    RasterCounters total;
    for (int trial = 0; trial < 120; ++trial) {
      RasterParams p = TestRasterParams(trial % 2 == 0);
      p.box = boxes[trial % std::size(boxes)];
      const std::vector<ScreenVertex> v = RandomVertices(gen, p.box, 150);
      // 1 to 200 triangles: tails of every length after the whole vectors.
      const auto tris = RandomTriangles(gen, v.size(), 1 + trial * 37 % 200);
      // Half the trials over random depths, so the depth test decides too.
      std::vector<float> z_ref(static_cast<size_t>(p.box.area()) + kSimdPadFloats, INFINITY);
      if (trial % 4 < 2)
        for (size_t i = 0; i < static_cast<size_t>(p.box.area()); ++i) z_ref[i] = background(gen);
      std::vector<float> z_simd = z_ref;
      RasterCounters st_ref, st_simd;
      RasterizeDepthReference(v, tris, p, z_ref.data(), &st_ref);
      RasterizeDepthFloatSimd(v, tris, p, z_simd.data(), &st_simd);
      ASSERT_EQ(st_simd, st_ref) << hwy::TargetName(target) << " trial " << trial;
      ASSERT_EQ(0, std::memcmp(z_ref.data(), z_simd.data(), z_ref.size() * sizeof(float)))
          << hwy::TargetName(target) << " trial " << trial;
      total += st_ref;
    }
    // Every branch was taken, many times.
    EXPECT_GT(total.culled_near, 500);
    EXPECT_GT(total.culled_degenerate, 500);
    EXPECT_GT(total.culled_backface, 1000);
    EXPECT_GT(total.culled_outside_box, 1000);
    EXPECT_GT(total.culled_between_pixels, 100);
    EXPECT_GT(total.triangles_rasterized, 1000);
    EXPECT_GT(total.fragments, 100000);
  }
  hwy::SetSupportedTargetsForTest(0);
}

// Large triangles over a whole 640 x 480 box: rows of many vectors.
TEST(RasterFloatSimd, LargeTrianglesBitIdenticalOnEveryTarget) {
  RasterParams p = TestRasterParams(false);
  p.box = PixelRect{0, 0, 640, 480};
  std::mt19937_64 gen(3);
  std::uniform_real_distribution<float> u(-100.f, 740.f), w(-100.f, 580.f), z(0.5f, 2.f);
  std::vector<ScreenVertex> v;
  std::vector<std::array<uint32_t, 3>> tris;
  for (uint32_t i = 0; i < 60; ++i) {
    for (int k = 0; k < 3; ++k) v.push_back({u(gen), w(gen), z(gen)});
    tris.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  for (int64_t target : hwy::SupportedAndGeneratedTargets()) {
    hwy::SetSupportedTargetsForTest(target);
    std::vector<float> z_ref(static_cast<size_t>(p.box.area()) + kSimdPadFloats, INFINITY), z_simd = z_ref;
    RasterCounters st_ref, st_simd;
    RasterizeDepthReference(v, tris, p, z_ref.data(), &st_ref);
    RasterizeDepthFloatSimd(v, tris, p, z_simd.data(), &st_simd);
    EXPECT_GT(st_ref.fragments, 1000000);
    ASSERT_EQ(st_simd, st_ref) << hwy::TargetName(target);
    ASSERT_EQ(0, std::memcmp(z_ref.data(), z_simd.data(), z_ref.size() * sizeof(float))) << hwy::TargetName(target);
  }
  hwy::SetSupportedTargetsForTest(0);
}

}  // namespace
}  // namespace mcpose::render

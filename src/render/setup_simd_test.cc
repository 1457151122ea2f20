// Batched triangle setup (setup_simd.cc) against its reference, SetupFixedTriangle, on every
// Highway target this CPU supports: the same snapped vertices, the same cull reason for every
// triangle it decides, and bit-identical z-buffers and statistics when rasterizing.
#include <cmath>
#include <cstring>
#include <random>
#include <set>
#include <vector>

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include "render/raster.h"
#include "render/raster_fixed.h"
#include "raster_test_util.h"

namespace mcpose::render {
namespace {

struct ScreenScene {
  std::vector<ScreenVertex> vertices;
  std::vector<std::array<uint32_t, 3>> triangles;
};

// Screen-space triangles of every kind setup meets: sub-pixel to hundreds of pixels, inside,
// across and outside the box, wider than the SIMD rows' span and than the fixed-point span,
// beyond the snap band and the guard band, not finite, behind the near plane, degenerate, and
// vertices on exact sub-pixel rounding ties.
ScreenScene RandomScreenScene(std::mt19937_64& gen, int n, const PixelRect& box) {
  std::uniform_real_distribution<float> cu(box.x0 - 60.f, box.x1 + 60.f), cv(box.y0 - 60.f, box.y1 + 60.f);
  std::uniform_real_distribution<float> z(0.3f, 1.5f), unit(-1.f, 1.f);
  std::uniform_int_distribution<int> kind(0, 19), tie(-4000, 4000);
  const float sizes[] = {0.3f, 1.f, 2.5f, 8.f, 40.f, 300.f};
  ScreenScene s;
  for (int i = 0; i < n; ++i) {
    const int k = kind(gen);
    const float size = sizes[k % 6];
    const float u0 = cu(gen), v0 = cv(gen);
    ScreenVertex p[3];
    for (auto& q : p) q = {u0 + size * unit(gen), v0 + size * unit(gen), z(gen)};
    switch (k) {
      case 6: p[1].u = p[0].u + 2500.f; break;                          // wider than kMaxSpanPx
      case 14: p[1].u = p[0].u + 1500.f; break;                         // wider than kMaxSimdSpanPx
      case 7: p[2].u = 1e6f; break;                                      // outside the guard band
      case 13: p[1].v = box.y0 - 2100.f; break;                          // beyond the snap band
      case 8: p[1].v = NAN; break;                                       // not finite
      case 9: p[0].z = 0.01f; break;                                     // near plane
      case 10: p[2] = p[1]; break;                                       // degenerate: a repeated vertex
      case 11: p[2] = {2 * p[1].u - p[0].u, 2 * p[1].v - p[0].v, p[2].z}; break;  // collinear
      case 12:  // rounding ties: coordinates on odd multiples of 1/32 pixel relative to the box
        for (auto& q : p) q.u = box.x0 + (2 * tie(gen) + 1) / 32.f, q.v = box.y0 + (2 * tie(gen) + 1) / 32.f;
        break;
      default: break;
    }
    const uint32_t b = static_cast<uint32_t>(s.vertices.size());
    for (const auto& q : p) s.vertices.push_back(q);
    s.triangles.push_back({b, b + 1, b + 2});
  }
  return s;
}

struct Counts {
  int64_t near = 0, backface = 0, outside = 0, between = 0;
};
Counts Of(const RasterCounters& s) {
  return {s.culled_near, s.culled_backface, s.culled_outside_box, s.culled_between_pixels};
}

// Every field of two set-up triangles (the depth plane bit for bit).
bool SameSetup(const FixedTriangle& a, const FixedTriangle& b) {
  bool same = a.x_lo == b.x_lo && a.x_hi == b.x_hi && a.y_lo == b.y_lo && a.y_hi == b.y_hi &&
              a.simd_fits == b.simd_fits && std::memcmp(&a.A, &b.A, sizeof(float)) == 0 &&
              std::memcmp(&a.B, &b.B, sizeof(float)) == 0 && std::memcmp(&a.C, &b.C, sizeof(float)) == 0;
  for (int k = 0; k < 3; ++k)
    same = same && a.w_row[k] == b.w_row[k] && a.step_x[k] == b.step_x[k] && a.step_y[k] == b.step_y[k];
  return same;
}

TEST(BatchedSetup, SnapsAndClassifiesAsSetupFixedTriangleOnEveryTarget) {
  const std::vector<int64_t> targets = hwy::SupportedAndGeneratedTargets();
  ASSERT_FALSE(targets.empty());
  for (int64_t target : targets) {
    hwy::SetSupportedTargetsForTest(target);
    std::mt19937_64 gen(7);
    for (int trial = 0; trial < 8; ++trial) {
      const RasterParams params = TestRasterParams(trial % 2 == 0);
      const ScreenScene s = RandomScreenScene(gen, 997, params.box);  // not a multiple of any vector
      SnappedVertices snapped;
      SnapVertices(s.vertices, params, &snapped);
      const float ox = static_cast<float>(params.box.x0), oy = static_cast<float>(params.box.y0);
      for (size_t i = 0; i < s.vertices.size(); ++i) {
        const ScreenVertex& v = s.vertices[i];
        const bool fast = std::fabs(v.u - ox) < kSnapBandPx && std::fabs(v.v - oy) < kSnapBandPx && v.z >= params.z_near_m;
        const int32_t p = snapped.packed[i];
        if (!fast) {
          ASSERT_EQ(p, kSnappedDeferred) << hwy::TargetName(target) << " vertex " << i;
          continue;
        }
        ASSERT_EQ(p >> 16, std::lrint((v.u - ox) * kSubpixelOne)) << hwy::TargetName(target) << " vertex " << i;
        ASSERT_EQ(static_cast<int16_t>(p & 0xffff), std::lrint((v.v - oy) * kSubpixelOne))
            << hwy::TargetName(target) << " vertex " << i;
      }

      // All triangles in one call: the survivors, in order, and the summed reasons.
      RasterCounters all;
      std::vector<uint32_t> survivors;
      const size_t kept = ClassifyTriangles(snapped, s.triangles, params, &all, &survivors);
      const std::set<uint32_t> kept_set(survivors.begin(), survivors.begin() + kept);
      ASSERT_EQ(kept_set.size(), kept);
      for (size_t j = 1; j < kept; ++j) ASSERT_LT(survivors[j - 1], survivors[j]);

      // The survivors set up a vector at a time: ready exactly when SetupFixedTriangle is,
      // field by field the same.
      std::vector<CompactTriangle> setups(kept);
      std::vector<uint8_t> ready(kept, 7);
      SetupSurvivors(snapped, s.vertices, s.triangles, params, std::span(survivors.data(), kept), setups.data(),
                     ready.data());
      int vector_ready = 0, too_wide = 0;
      for (size_t j = 0; j < kept; ++j) {
        const auto& tri = s.triangles[survivors[j]];
        FixedTriangle ft;
        const TriangleSetup ref =
            SetupFixedTriangle(s.vertices[tri[0]], s.vertices[tri[1]], s.vertices[tri[2]], params, &ft);
        const bool deferred = snapped.packed[tri[0]] == kSnappedDeferred ||
                              snapped.packed[tri[1]] == kSnappedDeferred || snapped.packed[tri[2]] == kSnappedDeferred;
        ASSERT_EQ(ready[j], deferred ? 0 : ref == TriangleSetup::kReady && ft.simd_fits)
            << hwy::TargetName(target) << " survivor " << j << " setup " << static_cast<int>(ref);
        too_wide += !deferred && ref == TriangleSetup::kReady && !ft.simd_fits;
        if (!ready[j]) continue;
        ++vector_ready;
        ASSERT_TRUE(SameSetup(Widen(setups[j]), ft)) << hwy::TargetName(target) << " survivor " << j;
      }
      EXPECT_GT(vector_ready, 0);
      EXPECT_GT(too_wide, 0) << "no triangle wider than the SIMD rows' span reached the setup";

      // One triangle per call: which reason it got, against SetupFixedTriangle.
      Counts expected;
      int undecided_culls = 0, culls = 0;
      for (size_t t = 0; t < s.triangles.size(); ++t) {
        const auto& tri = s.triangles[t];
        FixedTriangle ft;
        const TriangleSetup ref =
            SetupFixedTriangle(s.vertices[tri[0]], s.vertices[tri[1]], s.vertices[tri[2]], params, &ft);
        // The survivors' stage gives the same setup, field by field.
        FixedTriangle fb;
        ASSERT_EQ(SetupBatchedTriangle(s.vertices, snapped.packed.data(), tri, params, &fb), ref) << "triangle " << t;
        if (ref == TriangleSetup::kReady) {
          ASSERT_TRUE(SameSetup(fb, ft)) << "triangle " << t;
        }
        RasterCounters one;
        std::vector<uint32_t> one_survivor;
        const size_t one_kept = ClassifyTriangles(snapped, std::span(s.triangles).subspan(t, 1), params, &one,
                                                  &one_survivor);
        ASSERT_EQ(one_kept == 1, kept_set.count(static_cast<uint32_t>(t)) == 1) << "triangle " << t;
        const bool culled = ref == TriangleSetup::kCulledBackface ||
                            ref == TriangleSetup::kCulledOutsideBox || ref == TriangleSetup::kCulledBetweenPixels;
        culls += culled;
        if (one_kept == 1) {
          const bool all_snapped = snapped.packed[tri[0]] != kSnappedDeferred &&
                                   snapped.packed[tri[1]] != kSnappedDeferred &&
                                   snapped.packed[tri[2]] != kSnappedDeferred;
          undecided_culls += culled && all_snapped;
          continue;
        }
        ASSERT_TRUE(culled) << hwy::TargetName(target) << " triangle " << t << " decided but setup gives "
                            << static_cast<int>(ref);
        const Counts c = Of(one);
        const Counts want{0, ref == TriangleSetup::kCulledBackface,
                          ref == TriangleSetup::kCulledOutsideBox, ref == TriangleSetup::kCulledBetweenPixels};
        ASSERT_EQ(c.near, want.near) << hwy::TargetName(target) << " triangle " << t;
        ASSERT_EQ(c.backface, want.backface) << hwy::TargetName(target) << " triangle " << t;
        ASSERT_EQ(c.outside, want.outside) << hwy::TargetName(target) << " triangle " << t;
        ASSERT_EQ(c.between, want.between) << hwy::TargetName(target) << " triangle " << t;
        expected.near += want.near, expected.backface += want.backface, expected.outside += want.outside,
            expected.between += want.between;
      }
      EXPECT_EQ(Of(all).near, expected.near);
      EXPECT_EQ(Of(all).backface, expected.backface);
      EXPECT_EQ(Of(all).outside, expected.outside);
      EXPECT_EQ(Of(all).between, expected.between);
      // The pass earns its keep: of the culls among snapped (not deferred) triangles, only
      // slivers whose float area sign is uncertain are left over.
      EXPECT_LT(undecided_culls, culls / 50 + 1) << hwy::TargetName(target);
    }
  }
  hwy::SetSupportedTargetsForTest(0);
}

TEST(BatchedSetup, RasterizesBitIdenticallyOnEveryTarget) {
  const std::vector<int64_t> targets = hwy::SupportedAndGeneratedTargets();
  for (int64_t target : targets) {
    hwy::SetSupportedTargetsForTest(target);
    std::mt19937_64 gen(11);
    for (int trial = 0; trial < 8; ++trial) {
      const RasterParams params = TestRasterParams(trial % 2 == 0);
      const ScreenScene s = RandomScreenScene(gen, 301, params.box);
      for (RowKernel rows : {RowKernel::kScalar, RowKernel::kSimd}) {
        std::vector<float> z_ref(params.box.area() + kSimdPadFloats, INFINITY), z_batch = z_ref;
        RasterCounters st_ref, st_batch;
        RasterizeDepthFixedPoint(s.vertices, s.triangles, params, z_ref.data(), &st_ref, rows);
        SnappedVertices snapped;
        SnapVertices(s.vertices, params, &snapped);
        RasterizeDepthFixedPoint(s.vertices, s.triangles, params, z_batch.data(), &st_batch, rows, &snapped);
        ASSERT_EQ(0, std::memcmp(z_ref.data(), z_batch.data(), z_ref.size() * sizeof(float)))
            << hwy::TargetName(target) << " trial " << trial;
        EXPECT_EQ(st_batch, st_ref) << hwy::TargetName(target) << " trial " << trial;
        EXPECT_GT(st_ref.triangles_rasterized, 0);
      }
    }
  }
  hwy::SetSupportedTargetsForTest(0);
}

}  // namespace
}  // namespace mcpose::render

// Cluster culling: every triangle in one cluster, and the culls conservative: a dropped
// cluster's triangles are each culled by the fixed-point setup for the same reason.
#include "render/clusters.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <hwy/targets.h>

#include "render/raster_fixed.h"
#include "synthetic_mesh.h"

namespace mcpose::render {
namespace {

using testing::Blob;

TEST(Clusters, EveryTriangleInExactlyOneCluster) {
  const Mesh m = Blob();
  const ClusterSet cs = ClusterSet::Build(m);
  ASSERT_GT(cs.clusters.size(), 10u);
  auto sorted = [](std::vector<std::array<uint32_t, 3>> t) {
    for (auto& x : t) std::rotate(x.begin(), std::min_element(x.begin(), x.end()), x.end());  // keep winding
    std::sort(t.begin(), t.end());
    return t;
  };
  EXPECT_EQ(sorted(cs.triangles), sorted(m.triangles));
  uint32_t next = 0;
  for (const Cluster& c : cs.clusters) {
    EXPECT_EQ(c.first, next);
    EXPECT_GE(c.count, 1u);
    EXPECT_LE(c.count, ClusterSet::kMaxTriangles);
    next += c.count;
    Eigen::Vector3f lo = Eigen::Vector3f::Constant(INFINITY), hi = -lo;
    for (uint32_t k = c.first; k < c.first + c.count; ++k) {
      for (uint32_t v : cs.triangles[k]) {
        EXPECT_LE((m.vertices_m[v] - c.center).norm(), c.radius * 1.0001f + 1e-7f);
        lo = lo.cwiseMin(m.vertices_m[v]), hi = hi.cwiseMax(m.vertices_m[v]);
      }
    }
    EXPECT_EQ(c.box_lo, lo);  // exactly the bounds of its triangles' vertices
    EXPECT_EQ(c.box_hi, hi);
  }
  EXPECT_EQ(next, m.triangles.size());
}

TEST(Clusters, CullsAreConservativeOnRandomPoses) {
  const Mesh m = Blob();
  const ClusterSet cs = ClusterSet::Build(m);
  std::mt19937_64 gen(3);
  std::uniform_real_distribution<float> u(-1, 1);
  RasterParams p;
  p.fx = 1066.8f, p.fy = 1067.5f, p.cx = 313.0f, p.cy = 241.3f;
  std::vector<ScreenVertex> sv(m.vertices_m.size());
  int64_t dropped_back = 0, dropped_box = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Eigen::Matrix3f R = Eigen::AngleAxisf(3.14159f * u(gen), Eigen::Vector3f(u(gen), u(gen), u(gen)).normalized())
                                  .toRotationMatrix();
    const Eigen::Vector3f t(0.15f * u(gen), 0.1f * u(gen), 0.6f + 0.3f * u(gen));
    const int x0 = 150 + static_cast<int>(120 * u(gen)), y0 = 120 + static_cast<int>(100 * u(gen));
    p.box = PixelRect{x0, y0, x0 + 20 + static_cast<int>(60 * (1 + u(gen))), y0 + 20 + static_cast<int>(50 * (1 + u(gen)))};
    ProjectVertices(m.vertices_m, R, t, p, sv);
    const Eigen::Vector3f cam = -(R.transpose() * t);
    for (const Cluster& c : cs.clusters) {
      const ClusterCull why = CullCluster(c, R, t, cam, p);
      if (why == ClusterCull::kKeep) continue;
      (why == ClusterCull::kBackface ? dropped_back : dropped_box) += 1;
      for (uint32_t k = c.first; k < c.first + c.count; ++k) {
        const auto& tri = cs.triangles[k];
        FixedTriangle ft;
        const TriangleSetup s = SetupFixedTriangle(sv[tri[0]], sv[tri[1]], sv[tri[2]], p, &ft);
        // A dropped triangle must never have reached the rows.
        EXPECT_NE(s, TriangleSetup::kReady) << "trial " << trial << " triangle " << k;
        EXPECT_NE(s, TriangleSetup::kFloatPath) << "trial " << trial << " triangle " << k;
        if (why == ClusterCull::kOutsideBox) {
          EXPECT_TRUE(s == TriangleSetup::kCulledOutsideBox || s == TriangleSetup::kCulledBackface ||
                      s == TriangleSetup::kCulledDegenerate || s == TriangleSetup::kCulledNear)
              << "trial " << trial << " triangle " << k;
        }
      }
    }
  }
  // Both tests fired often enough to mean something.
  EXPECT_GT(dropped_back, 300);
  EXPECT_GT(dropped_box, 300);
}

// The vector of clusters against CullCluster on every target: the same decision for every
// cluster, over poses that put spheres and corners behind the near plane, boxes in and out of
// view, and cluster counts that leave a partial last vector (1 to 17 clusters, and all). With
// back faces rasterized (every third pose), no cluster is dropped as back-facing.
TEST(Clusters, SimdCullingMatchesTheReferenceOnEveryTarget) {
  const Mesh m = Blob();
  const ClusterSet all = ClusterSet::Build(m);
  ASSERT_EQ(all.soa.size(), all.soa_stride * kClusterFields);
  std::vector<ClusterSet> sets;
  for (size_t n : {size_t{1}, size_t{3}, size_t{8}, size_t{9}, size_t{16}, size_t{17}}) {
    ClusterSet part;
    part.clusters.assign(all.clusters.begin(), all.clusters.begin() + static_cast<std::ptrdiff_t>(n));
    part.BuildSoa();
    sets.push_back(std::move(part));
  }
  sets.push_back(all);
  RasterParams p;
  p.fx = 1066.8f, p.fy = 1067.5f, p.cx = 313.0f, p.cy = 241.3f;
  for (int64_t target : hwy::SupportedAndGeneratedTargets()) {
    hwy::SetSupportedTargetsForTest(target);
    std::mt19937_64 gen(17);
    std::uniform_real_distribution<float> u(-1, 1);
    int64_t seen[3] = {0, 0, 0}, back_without_culling = 0, outside_without_culling = 0;
    for (int trial = 0; trial < 400; ++trial) {
      p.cull_backfaces = trial % 3 != 0;
      const Eigen::Matrix3f R =
          Eigen::AngleAxisf(3.14159f * u(gen), Eigen::Vector3f(u(gen), u(gen), u(gen)).normalized()).toRotationMatrix();
      // Every fourth pose close enough that some spheres and boxes cross the near plane.
      const float z = trial % 4 == 0 ? 0.1f + 0.06f * u(gen) : 0.6f + 0.3f * u(gen);
      const Eigen::Vector3f t(0.15f * u(gen), 0.1f * u(gen), z);
      const int x0 = 150 + static_cast<int>(200 * u(gen)), y0 = 120 + static_cast<int>(150 * u(gen));
      p.box = PixelRect{x0, y0, x0 + 5 + static_cast<int>(60 * (1 + u(gen))), y0 + 5 + static_cast<int>(50 * (1 + u(gen)))};
      const Eigen::Vector3f cam = -(R.transpose() * t);
      for (const ClusterSet& cs : sets) {
        std::vector<ClusterCull> simd(cs.clusters.size() + 1, static_cast<ClusterCull>(7));
        CullClustersSimd(cs, R, t, cam, p, simd.data());
        for (size_t i = 0; i < cs.clusters.size(); ++i) {
          const ClusterCull ref = CullCluster(cs.clusters[i], R, t, cam, p);
          ASSERT_EQ(static_cast<int>(simd[i]), static_cast<int>(ref))
              << hwy::TargetName(target) << " trial " << trial << " cluster " << i << " of " << cs.clusters.size();
          ++seen[static_cast<int>(ref)];
          if (!p.cull_backfaces) {
            back_without_culling += ref == ClusterCull::kBackface;
            outside_without_culling += ref == ClusterCull::kOutsideBox;
          }
        }
        EXPECT_EQ(static_cast<int>(simd.back()), 7) << "wrote past the last cluster";
      }
    }
    for (int64_t n : seen) EXPECT_GT(n, 1000) << hwy::TargetName(target);
    EXPECT_EQ(back_without_culling, 0) << hwy::TargetName(target);
    EXPECT_GT(outside_without_culling, 300) << hwy::TargetName(target);
  }
  hwy::SetSupportedTargetsForTest(0);
}

}  // namespace
}  // namespace mcpose::render

// The hardware numerics against exact arithmetic and against float: the inlier bounds are the
// real comparison |2^36 / IZ - 4 d| < 4 eps, the projection is within a sub-pixel of the float
// pinhole, the stepped IZ plane equals the plane evaluated directly, and every triangle the
// core leaves out is counted under its reason.
#include "hw/raster_core.h"

#include <cmath>
#include <cstdlib>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "core/rng.h"

namespace mcpose::hw {
namespace {

constexpr int64_t kTwo36 = int64_t{1} << kInverseDepthBits;

TEST(HwRasterCore, InlierBoundsAreTheExactComparison) {
  Rng rng(11, 1);
  int inliers = 0, occluded = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const auto d = static_cast<int32_t>(rng.Uniform(1, 60000));
    const auto eps = static_cast<int32_t>(rng.Uniform(1, 600));
    const DepthBounds b = InlierBounds(d, eps);
    // IZ near either bound, and anywhere.
    const int64_t centre = kTwo36 / (4 * int64_t{d});
    const int64_t candidates[] = {b.lo - 1, b.lo, b.lo + 1, int64_t{b.hi} - 1, b.hi, int64_t{b.hi} + 1, centre,
                                  static_cast<int64_t>(rng.Uniform(1, 1 << 25))};
    for (int64_t iz : candidates) {
      if (iz <= 0 || iz > (int64_t{1} << 32) - 1) continue;
      const auto v = static_cast<uint32_t>(iz);
      // |2^36 / iz - 4 d| < 4 eps  <=>  |2^36 - 4 d iz| < 4 eps iz (iz > 0), exact in 64 bits.
      const bool inlier = std::llabs(kTwo36 - 4 * int64_t{d} * iz) < 4 * int64_t{eps} * iz;
      // 2^36 / iz >= 4 (d + eps): something observed in front of the rendered surface by eps.
      const bool behind = kTwo36 >= 4 * (int64_t{d} + eps) * iz;
      ASSERT_EQ(b.lo <= v && v <= b.hi, inlier) << "d " << d << " eps " << eps << " iz " << iz;
      ASSERT_EQ(v < b.lo, behind) << "d " << d << " eps " << eps << " iz " << iz;
      inliers += inlier, occluded += behind;
    }
  }
  EXPECT_GT(inliers, 1000);
  EXPECT_GT(occluded, 1000);
  // No depth: neither.
  const DepthBounds none = InlierBounds(0, 100);
  const std::vector<uint32_t> z = {0, 1, 5000000};
  const std::vector<DepthBounds> bounds(3, none);
  EXPECT_EQ(CountBox(z, bounds), (Counts{0, 2, 0}));
}

TEST(HwRasterCore, DepthUnitsOfRealDepthAreExact) {
  // YCB-Video's depth: uint16 in 0.1 mm, read as metres.
  for (int raw : {1, 523, 10000, 65535}) {
    const float z = static_cast<float>(raw / 10000.0);
    EXPECT_EQ(ObservedDepthUnits(std::vector<float>{z})[0], raw);
  }
  EXPECT_EQ(ObservedDepthUnits(std::vector<float>{0.f, -1.f})[1], 0);
  EXPECT_EQ(EpsUnits(0.01f), 100);
  EXPECT_EQ(EpsUnits(1e-9f), 1);
}

TEST(HwRasterCore, ProjectionIsWithinAFifthOfAPixelOfTheFloatPinhole) {
  Rng rng(5, 2);
  const double fx = 1066.778, fy = 1067.487, cx = 312.9869, cy = 241.3109;
  const int x0 = 250, y0 = 180;
  const Camera camera = QuantizeCamera(fx, fy, cx, cy, x0, y0, 130, 120, 0.05);
  double worst = 0;
  for (int trial = 0; trial < 5000; ++trial) {
    const Eigen::Vector3f axis = Eigen::Vector3f::Random().normalized();
    const Eigen::Matrix3f R = Eigen::AngleAxisf(static_cast<float>(rng.Uniform(-3.14, 3.14)), axis).toRotationMatrix();
    const Eigen::Vector3f t(static_cast<float>(rng.Uniform(-0.1, 0.1)), static_cast<float>(rng.Uniform(-0.1, 0.1)),
                            static_cast<float>(rng.Uniform(0.4, 1.5)));
    const Eigen::Vector3f X = Eigen::Vector3f::Random() * 0.15f;
    std::vector<ModelVertex> q;
    ASSERT_TRUE(QuantizeModel(std::vector<Eigen::Vector3f>{X}, &q));
    const Vertex v = TransformVertex(QuantizePose(R, t), camera, q[0]);
    const Eigen::Vector3d c = (R.cast<double>() * X.cast<double>() + t.cast<double>());
    ASSERT_FALSE(v.near);
    ASSERT_TRUE(v.in_band);
    EXPECT_NEAR(v.Z * kPositionUnitM, c.z(), 4 * kPositionUnitM);
    const double u = (fx * c.x() / c.z() + cx - x0) * 16, w = (fy * c.y() / c.z() + cy - y0) * 16;
    worst = std::max({worst, std::fabs(v.U - u), std::fabs(v.V - w)});
    EXPECT_NEAR(static_cast<double>(v.iz), kTwo36 / (c.z() / kPositionUnitM), 0.001 * v.iz);
  }
  // Rounding the model and the translation to 25 um moves a vertex by up to about 40 um: under
  // 3/16 pixel here (0.4 m and further), the rounding of U itself included.
  EXPECT_LT(worst, 3.0);
  EXPECT_GT(worst, 0.0);
}

// The IZ plane at a pixel, evaluated directly from the triangle's vertices.
int64_t DirectIz(const Vertex v[3], int64_t px, int64_t py) {
  // Barycentric weights from the edge functions, orientation-free.
  const int64_t X[3] = {v[0].U, v[1].U, v[2].U}, Y[3] = {v[0].V, v[1].V, v[2].V};
  const int64_t area = (X[1] - X[0]) * (Y[2] - Y[0]) - (Y[1] - Y[0]) * (X[2] - X[0]);
  int64_t sum = 0;
  for (int k = 0; k < 3; ++k) {
    const int i = (k + 1) % 3, j = (k + 2) % 3;  // the edge i -> j, opposite k
    const int64_t e = (X[j] - X[i]) * (py - Y[i]) - (Y[j] - Y[i]) * (px - X[i]);
    sum += e * int64_t{v[k].iz};
  }
  return area > 0 ? RoundDiv(sum << kPlaneFracBits, area) >> kPlaneFracBits
                  : RoundDiv(-sum << kPlaneFracBits, -area) >> kPlaneFracBits;
}

TEST(HwRasterCore, SteppedPlaneEqualsThePlaneEvaluatedDirectly) {
  Rng rng(3, 3);
  const Camera camera = QuantizeCamera(1000, 1000, 100, 100, 0, 0, 200, 200, 0.05);
  int64_t pixels = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Vertex v[3];
    for (Vertex& p : v) {
      p.U = static_cast<int32_t>(rng.Uniform(-200, 3400)), p.V = static_cast<int32_t>(rng.Uniform(-200, 3400));
      p.Z = static_cast<int32_t>(rng.Uniform(20000, 60000));
      p.iz = static_cast<uint32_t>(kTwo36 / p.Z);
      p.in_band = true;
    }
    Triangle t;
    if (SetupTriangle(v[0], v[1], v[2], camera, /*cull_backfaces=*/false, &t) != Setup::kReady) continue;
    std::vector<uint32_t> zbuf(200 * 200, 0);
    const int64_t covered = FillTriangle(t, zbuf.data(), 200);
    for (int y = t.y_lo; y <= t.y_hi; ++y)
      for (int x = t.x_lo; x <= t.x_hi; ++x) {
        const uint32_t z = zbuf[static_cast<size_t>(y) * 200 + x];
        if (z == 0) continue;
        ++pixels;
        // Each step adds at most half a unit of the 8 fraction bits: under 2 units over 255 pixels.
        ASSERT_LE(std::llabs(int64_t{z} - DirectIz(v, int64_t{x} * 16, int64_t{y} * 16)), 2);
        // Inside the triangle, IZ lies between the vertices' (1/z is affine over the screen).
        ASSERT_GE(z + 2, std::min({v[0].iz, v[1].iz, v[2].iz}));
        ASSERT_LE(z, std::max({v[0].iz, v[1].iz, v[2].iz}) + 2);
      }
    EXPECT_LE(covered, int64_t{t.x_hi - t.x_lo + 1} * (t.y_hi - t.y_lo + 1));
  }
  EXPECT_GT(pixels, 100000);
}

TEST(HwRasterCore, EachTriangleLeftOutIsCountedUnderItsReason) {
  const Camera camera = QuantizeCamera(1000, 1000, 50, 50, 0, 0, 100, 100, 0.05);
  auto vertex = [](int U, int V, int Z = 40000) {
    Vertex p;
    p.U = U, p.V = V, p.Z = Z, p.iz = static_cast<uint32_t>(kTwo36 / Z), p.in_band = true;
    return p;
  };
  Triangle t;
  // Front faces have negative area (y down): (0,0) (0,16k) (16k,0) in sub-pixels.
  EXPECT_EQ(SetupTriangle(vertex(0, 0), vertex(0, 320), vertex(320, 0), camera, true, &t), Setup::kReady);
  EXPECT_EQ(SetupTriangle(vertex(0, 0), vertex(320, 0), vertex(0, 320), camera, true, &t), Setup::kBackface);
  EXPECT_EQ(SetupTriangle(vertex(0, 0), vertex(320, 0), vertex(0, 320), camera, false, &t), Setup::kReady);
  EXPECT_EQ(SetupTriangle(vertex(0, 0), vertex(16, 16), vertex(32, 32), camera, true, &t), Setup::kDegenerate);
  EXPECT_EQ(SetupTriangle(vertex(-900, -900), vertex(-900, -800), vertex(-800, -900), camera, true, &t),
            Setup::kOutsideBox);
  EXPECT_EQ(SetupTriangle(vertex(0, 0), vertex(0, 16 * 300), vertex(16 * 300, 0), camera, true, &t),
            Setup::kTooLarge);
  EXPECT_EQ(SetupTriangle(vertex(1, 1), vertex(1, 9), vertex(9, 1), camera, true, &t), Setup::kBetweenPixels);
  Vertex near = vertex(0, 0);
  near.near = true;
  EXPECT_EQ(SetupTriangle(near, vertex(0, 320), vertex(320, 0), camera, true, &t), Setup::kNear);
  Vertex far_off = vertex(0, 0);
  far_off.in_band = false;
  EXPECT_EQ(SetupTriangle(far_off, vertex(0, 320), vertex(320, 0), camera, true, &t), Setup::kGuardBand);
  // A vertex behind the camera is near; one far to the side is outside the guard band.
  const Pose identity = QuantizePose(Eigen::Matrix3f::Identity(), Eigen::Vector3f(0, 0, 0.5f));
  EXPECT_TRUE(TransformVertex(identity, camera, ModelVertex{0, 0, -20000}).near);
  EXPECT_FALSE(TransformVertex(identity, camera, ModelVertex{20000, 0, 0}).in_band);  // 0.5 m aside at 0.5 m
  EXPECT_TRUE(TransformVertex(identity, camera, ModelVertex{400, 0, 0}).in_band);
}

TEST(HwRasterCore, ModelsBeyondTheRangeAreRefused) {
  std::vector<ModelVertex> q;
  EXPECT_TRUE(QuantizeModel(std::vector<Eigen::Vector3f>{{0.8f, -0.8f, 0.1f}}, &q));
  EXPECT_EQ(q[0][0], 32000);
  EXPECT_FALSE(QuantizeModel(std::vector<Eigen::Vector3f>{{0.9f, 0.f, 0.f}}, &q));
  EXPECT_EQ(q[0][0], 32000);  // untouched
}

}  // namespace
}  // namespace mcpose::hw

#include "score/inlier.h"

#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <hwy/targets.h>

namespace mcpose::score {
namespace {

struct Buffers {
  render::PixelRect box{100, 50, 160, 90};
  std::vector<float> rendered, observed;
};

Buffers RandomBuffers(std::mt19937_64& gen) {
  Buffers b;
  std::uniform_real_distribution<float> z(0.6f, 0.9f), u(0.f, 1.f), noise(-0.02f, 0.02f);
  for (int i = 0; i < b.box.area(); ++i) {
    const float surface = z(gen);
    b.rendered.push_back(u(gen) < 0.3f ? INFINITY : surface + noise(gen));
    b.observed.push_back(u(gen) < 0.1f ? 0.f : surface + noise(gen));
  }
  return b;
}

TEST(Inlier, OneDimensionalCountsMatchNaiveLoop) {
  std::mt19937_64 gen(5);
  for (int trial = 0; trial < 50; ++trial) {
    const Buffers b = RandomBuffers(gen);
    const float eps = 0.01f;
    InlierCounts naive;
    for (size_t i = 0; i < b.rendered.size(); ++i) {
      if (b.observed[i] > 0) ++naive.observed;
      if (std::isinf(b.rendered[i])) continue;
      ++naive.rendered;
      if (b.observed[i] > 0 && std::abs(b.rendered[i] - b.observed[i]) < eps) ++naive.inliers;
      if (b.observed[i] > 0 && b.observed[i] <= b.rendered[i] - eps) ++naive.occluded;
    }
    EXPECT_EQ(CountInliers1D(b.rendered, b.observed, eps), naive);
    EXPECT_EQ(CountObserved(b.observed), naive.observed);
  }
}

TEST(Inlier, RectCountsMatchWholeBoxWhenNothingIsRenderedOutside) {
  std::mt19937_64 gen(7);
  for (int trial = 0; trial < 50; ++trial) {
    Buffers b = RandomBuffers(gen);
    const int w = b.box.width(), h = b.box.height();
    std::uniform_int_distribution<int> ux(0, w), uy(0, h);
    int x0 = ux(gen), x1 = ux(gen), y0 = uy(gen), y1 = uy(gen);
    if (x0 > x1) std::swap(x0, x1);
    if (y0 > y1) std::swap(y0, y1);
    const render::PixelRect rect{x0, y0, x1, y1};
    // Outside the rect: nothing rendered in the whole-box buffer, garbage in the fast one.
    std::vector<float> whole = b.rendered, garbage = b.rendered;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        if (x < x0 || x >= x1 || y < y0 || y >= y1) whole[y * w + x] = INFINITY, garbage[y * w + x] = 0.7f;
    EXPECT_EQ(CountInliers1DInRect(garbage.data(), b.observed.data(), w, rect, CountObserved(b.observed), 0.01f),
              CountInliers1D(whole, b.observed, 0.01f));
  }
}

TEST(Inlier, SimdRectCountsEqualTheScalarReferenceOnEveryTarget) {
  for (int64_t target : hwy::SupportedAndGeneratedTargets()) {
    hwy::SetSupportedTargetsForTest(target);
    std::mt19937_64 gen(11);
    for (int trial = 0; trial < 50; ++trial) {
      Buffers b = RandomBuffers(gen);
      const int w = b.box.width(), h = b.box.height();
      // Depths exactly eps apart and exactly equal: the comparisons' edge cases.
      for (int i = 0; i < w * h; i += 7)
        if (b.observed[i] > 0) b.rendered[i] = b.observed[i] + (i % 2 ? 0.01f : 0.f);
      std::uniform_int_distribution<int> ux(0, w), uy(0, h);
      int x0 = ux(gen), x1 = ux(gen), y0 = uy(gen), y1 = uy(gen);
      if (x0 > x1) std::swap(x0, x1);
      if (y0 > y1) std::swap(y0, y1);
      const render::PixelRect rect{x0, y0, x1, y1};
      // Invalid observed depths of every kind: 0, negative, NaN.
      for (int i = 3; i < w * h; i += 11) b.observed[i] = i % 3 == 0 ? -0.5f : i % 3 == 1 ? NAN : 0.f;
      const int32_t n_valid = CountObserved(b.observed);
      const std::vector<float> or_nan = ObservedOrNaN(b.observed);
      EXPECT_EQ(CountInliers1DInRectSimd(b.rendered.data(), or_nan.data(), w, rect, n_valid, 0.01f),
                CountInliers1DInRect(b.rendered.data(), b.observed.data(), w, rect, n_valid, 0.01f))
          << hwy::TargetName(target) << " trial " << trial;
    }
  }
  hwy::SetSupportedTargetsForTest(0);
}

TEST(Inlier, ThreeDimensionalCountsMatchBruteForce) {
  std::mt19937_64 gen(6);
  Intrinsics K{1066.778, 1067.487, 312.9869, 241.3109, 640, 480};
  for (int trial = 0; trial < 5; ++trial) {
    Buffers b = RandomBuffers(gen);
    // A fifth of the rendered pixels 0.5 m behind every observed point: hidden, not inliers.
    std::uniform_real_distribution<float> u(0.f, 1.f);
    for (float& z : b.rendered)
      if (!std::isinf(z) && u(gen) < 0.2f) z += 0.5f;
    const float eps = 0.01f;
    ObservedCloud cloud(K, b.box, b.observed);
    auto back = [&](int i, float z) {
      const int x = b.box.x0 + i % b.box.width(), y = b.box.y0 + i / b.box.width();
      return Eigen::Vector3f(float((x - K.cx) / K.fx) * z, float((y - K.cy) / K.fy) * z, z);
    };
    InlierCounts naive;
    naive.observed = CountObserved(b.observed);
    for (size_t i = 0; i < b.rendered.size(); ++i) {
      if (std::isinf(b.rendered[i])) continue;
      ++naive.rendered;
      const Eigen::Vector3f p = back(i, b.rendered[i]);
      bool hit = false;
      for (size_t j = 0; j < b.observed.size() && !hit; ++j)
        hit = b.observed[j] > 0 && (back(j, b.observed[j]) - p).squaredNorm() < eps * eps;
      naive.inliers += hit;
      // Not a 3-D inlier, and the observed surface at this pixel is in front by >= eps.
      naive.occluded += !hit && b.observed[i] > 0 && b.observed[i] <= b.rendered[i] - eps;
    }
    EXPECT_EQ(cloud.CountInliers3D(b.rendered, eps), naive);
    EXPECT_GT(naive.occluded, 0);
  }
}

}  // namespace
}  // namespace mcpose::score

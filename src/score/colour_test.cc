#include "score/colour.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <hwy/targets.h>
#include <Eigen/Geometry>

#include "core/rng.h"
#include "mcpose/simd.h"
#include "score/inlier.h"

namespace mcpose::score {
namespace {

// A random grid, z-buffer, observed depth and colour; random rigid transforms from camera to
// model that put the rendered points around the grid (some inside, some outside).
struct RandomCase {
  std::vector<uint32_t> cells;
  ColourLookup lookup;
  std::vector<float> rendered, observed, observed_or_nan;
  std::vector<uint32_t> rgba;
  ColourSample sample;
};

RandomCase MakeCase(uint64_t seed, int width, int height) {
  RandomCase c;
  Rng rng(seed, 3);
  c.lookup.nx = 7 + static_cast<int>(rng.Uniform() * 20), c.lookup.ny = 5 + static_cast<int>(rng.Uniform() * 20);
  c.lookup.nz = 3 + static_cast<int>(rng.Uniform() * 20);
  c.cells.resize(static_cast<size_t>(c.lookup.nx) * c.lookup.ny * c.lookup.nz);
  for (uint32_t& v : c.cells) {
    v = static_cast<uint32_t>(rng.NextU64());
    if (rng.Uniform() < 0.2) v &= 0x00ffffffu;  // unknown
  }
  c.lookup.cells = c.cells.data();
  const float cell = static_cast<float>(rng.Uniform(0.002, 0.006));
  c.lookup.inv_cell = 1.0f / cell;
  for (int a = 0; a < 3; ++a) c.lookup.origin[a] = -0.5f * cell * (a == 0 ? c.lookup.nx : a == 1 ? c.lookup.ny : c.lookup.nz);
  const size_t n = static_cast<size_t>(width) * height;
  c.rendered.resize(n + 64), c.observed.resize(n), c.rgba.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const double u = rng.Uniform();
    c.rendered[i] = u < 0.3 ? INFINITY : static_cast<float>(rng.Uniform(0.55, 0.65));
    c.observed[i] = rng.Uniform() < 0.1 ? 0.f : c.rendered[i] == INFINITY ? 0.6f : c.rendered[i] + static_cast<float>(rng.Uniform(-0.015, 0.015));
    c.rgba[i] = static_cast<uint32_t>(rng.NextU64()) | (rng.Uniform() < 0.05 ? 0u : 0xff000000u);
    if ((c.rgba[i] >> 24) != 0xff) c.rgba[i] &= 0x00ffffffu;
  }
  c.observed_or_nan = ObservedOrNaN(c.observed);
  ColourSample& s = c.sample;
  s.rendered = c.rendered.data(), s.observed = c.observed.data(), s.observed_or_nan = c.observed_or_nan.data();
  s.observed_rgba = c.rgba.data();
  s.stride = width;
  const int x0 = static_cast<int>(rng.Uniform() * width / 3), y0 = static_cast<int>(rng.Uniform() * height / 3);
  s.rect = render::PixelRect{x0, y0, x0 + 1 + static_cast<int>(rng.Uniform() * (width - x0 - 1)),
                             y0 + 1 + static_cast<int>(rng.Uniform() * (height - y0 - 1))};
  s.grid_x0 = static_cast<float>(100 + static_cast<int>(rng.Uniform() * 100));
  s.grid_y0 = static_cast<float>(80 + static_cast<int>(rng.Uniform() * 100));
  s.cx = s.grid_x0 + 0.5f * width, s.cy = s.grid_y0 + 0.5f * height;
  s.inv_fx = static_cast<float>(1.0 / rng.Uniform(300, 1100)), s.inv_fy = static_cast<float>(1.0 / rng.Uniform(300, 1100));
  // A rotation about a random axis, and the translation that takes the camera point at 0.6 m on
  // the optical axis to the model origin.
  const Eigen::Vector3f axis = Eigen::Vector3f(rng.Normal(), rng.Normal(), rng.Normal()).normalized();
  const Eigen::Matrix3f R = Eigen::AngleAxisf(static_cast<float>(rng.Uniform(0, 3)), axis).toRotationMatrix();
  const Eigen::Vector3f t = -R * Eigen::Vector3f(0, 0, 0.6f);
  for (int i = 0; i < 9; ++i) s.R_model_cam[i] = R(i / 3, i % 3);
  for (int a = 0; a < 3; ++a) s.t_model_cam[a] = t[a];
  return c;
}

// The reference, written again as plainly as possible: double-checks CountColour's arithmetic
// (sums of integers) on the pixels it counts.
TEST(Colour, ReferenceCountsEveryQualifyingPixel) {
  const RandomCase c = MakeCase(1, 120, 90);
  const ColourStats s = CountColour(c.sample, c.lookup);
  EXPECT_GT(s.n, 20);
  int64_t n = 0;
  for (int y = c.sample.rect.y0; y < c.sample.rect.y1; ++y)
    for (int x = c.sample.rect.x0; x < c.sample.rect.x1; ++x) {
      const size_t i = static_cast<size_t>(y) * c.sample.stride + x;
      n += c.rendered[i] != INFINITY && c.observed[i] > 0 && std::fabs(c.rendered[i] - c.observed[i]) < c.sample.eps_m &&
           (c.rgba[i] >> 24) != 0;
    }
  EXPECT_LT(s.n, n);  // some points fall outside the grid or on unknown cells
  EXPECT_GE(s.mm[0] * s.n, s.m[0] * s.m[0]);
}

// The SIMD kernel gives the reference's sums on random inputs, every pixel or every second one,
// on every SIMD target.
TEST(Colour, SimdKernelEqualsTheReferenceOnEveryTarget) {
  for (int64_t target : hwy::SupportedAndGeneratedTargets()) {
    hwy::SetSupportedTargetsForTest(target);
    int64_t counted = 0;
    for (uint64_t seed = 0; seed < 120; ++seed) {
      const int w = 1 + static_cast<int>(seed * 7 % 97), h = 1 + static_cast<int>(seed * 5 % 61);
      RandomCase c = MakeCase(seed, w, h);
      c.sample.step = 1 + static_cast<int>(seed % 4);
      const ColourStats ref = CountColour(c.sample, c.lookup);
      ASSERT_EQ(CountColourSimd(c.sample, c.lookup), ref) << hwy::TargetName(target) << " seed " << seed;
      counted += ref.n;
    }
    EXPECT_GT(counted, 1000) << hwy::TargetName(target);
  }
  hwy::SetSupportedTargetsForTest(0);
}

TEST(Colour, AgreementIsOneForTheSamePatternUnderAnyGainAndNeutralWithoutOne) {
  // Model and observed colours of n pixels: a pattern, and the pattern under another light.
  auto stats = [](int n, auto model, auto observed) {
    ColourStats s;
    for (int i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) {
        const int64_t m = model(i, c), o = observed(i, c);
        if (c == 0) ++s.n;
        s.m[c] += m, s.o[c] += o, s.mm[c] += m * m, s.oo[c] += o * o, s.mo[c] += m * o;
      }
    return s;
  };
  auto pattern = [](int i, int c) { return (i * 37 + c * 91) % 200 + 20; };
  EXPECT_NEAR(ColourAgreement(stats(100, pattern, pattern), 10), 1.0, 1e-12);
  EXPECT_NEAR(ColourAgreement(stats(100, pattern, [&](int i, int c) { return pattern(i, c) / 2 + 10; }), 10), 1.0,
              0.01);
  EXPECT_NEAR(ColourAgreement(stats(100, pattern, [&](int i, int c) { return 240 - pattern(i, c); }), 10), 0.0, 1e-12);
  auto flat = [](int, int) { return 128; };
  EXPECT_EQ(ColourAgreement(stats(100, pattern, flat), 10), kNeutralAgreement);  // the frame does not vary
  EXPECT_EQ(ColourAgreement(stats(5, pattern, pattern), 10), kNeutralAgreement);  // too few pixels
}

// Intensity-hue statistics (channel 0 the intensity, 1 and 2 the hue) of n pixels.
ColourStats IntensityHueStats(int n, auto model, auto observed) {
  ColourStats s;
  for (int i = 0; i < n; ++i) {
    ++s.n;
    for (int c = 0; c < 3; ++c) {
      const int64_t m = model(i, c), o = observed(i, c);
      s.m[c] += m, s.o[c] += o, s.mm[c] += m * m, s.oo[c] += o * o, s.mo[c] += m * o;
    }
  }
  return s;
}

// Hue first: on a surface with a coloured pattern the hue decides, whatever shading does to the
// intensity; on an achromatic one the intensity decides, the hue's noise left out.
TEST(Colour, HueFirstLetsTheHueDecideWhereTheModelHasAColouredPattern) {
  // A coloured label: hue stripes (a standard deviation of about 34 levels) and their intensity.
  auto label = [](int i, int c) { return c == 0 ? 90 + (i % 7) * 20 : 60 + ((i / 3 + c) % 4) * 30; };
  // The right pose under a lamp at one side: the hue as the label's, the intensity a shading ramp
  // that has nothing to do with the label's.
  auto right = [&](int i, int c) { return c == 0 ? 40 + (i * 180) / 300 : label(i, c); };
  // A twin whose label lies elsewhere: its hue does not match, its intensity happens to follow
  // the ramp.
  auto twin_model = [&](int i, int c) { return c == 0 ? 40 + (i * 180) / 300 : label(i + 1, c); };
  const ColourStats truth = IntensityHueStats(300, label, right);
  const ColourStats twin = IntensityHueStats(300, twin_model, right);
  // Intensity and hue together: the shading ramp lets the twin win.
  EXPECT_LT(ColourAgreement(truth, 20), ColourAgreement(twin, 20));
  // Hue first: the truth wins; its agreement is its hue's alone, 1.
  EXPECT_GT(ColourAgreement(truth, 20, 8), ColourAgreement(twin, 20, 8) + 0.15);
  EXPECT_NEAR(ColourAgreement(truth, 20, 8), 1.0, 1e-12);

  // An achromatic print (black on white): the model's hue varies by a level or three of noise,
  // so the intensity alone decides; the noisy hue neither helps nor dilutes it.
  auto print = [](int i, int c) { return c == 0 ? ((i / 4) % 3 == 0 ? 30 : 220) : 85 + (i * 13 + c * 5) % 9 - 4; };
  auto seen = [](int i, int c) { return c == 0 ? ((i / 4) % 3 == 0 ? 25 : 200) : 85 + (i * 29 + c) % 9 - 4; };
  const ColourStats achromatic = IntensityHueStats(300, print, seen);
  EXPECT_NEAR(ColourAgreement(achromatic, 20, 8), 1.0, 1e-12);
  EXPECT_LT(ColourAgreement(achromatic, 20), 0.9);  // together, the hue's noise pulls it down
  // 0 leaves the mean of every channel that varies.
  EXPECT_EQ(ColourAgreement(achromatic, 20, 0), ColourAgreement(achromatic, 20));
}

}  // namespace
}  // namespace mcpose::score

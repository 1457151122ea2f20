#include "mcpose/photometric.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace mcpose::synth {
namespace {

ColourImage Ramp(int w = 64, int h = 48) {
  ColourImage im;
  im.width = w, im.height = h;
  im.rgba.resize(4 * static_cast<size_t>(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      uint8_t* p = im.rgba.data() + 4 * (static_cast<size_t>(y) * w + x);
      p[0] = static_cast<uint8_t>(4 * x), p[1] = static_cast<uint8_t>(5 * y), p[2] = static_cast<uint8_t>(2 * (x + y));
      p[3] = static_cast<uint8_t>(x == 0 ? 0 : 255);
    }
  return im;
}

PhotometricTransform Parse(const std::string& s) {
  auto t = ParsePhotometricTransform(s);
  EXPECT_TRUE(t.ok()) << t.status().ToString();
  return t.ok() ? *t : PhotometricTransform{};
}

TEST(Photometric, SpellingsRoundTripAndBadOnesAreRefusedByName) {
  for (const char* s : {"none", "exposure:0.5", "gamma:1.6", "white-balance:1.3,1,0.7", "saturation:1.5", "clip:0.8",
                        "jpeg:30", "noise:8"})
    EXPECT_EQ(Parse(s).ToString(), s);
  for (const char* s : {"", "bright:2", "exposure", "exposure:0", "exposure:-1", "exposure:nan", "gamma:0.01",
                        "white-balance:1,1", "white-balance:1,0,1", "clip:1.5", "clip:0", "jpeg:0", "jpeg:30.5",
                        "jpeg:101", "noise:-1", "noise:500", "none:1", "saturation:x"}) {
    auto t = ParsePhotometricTransform(s);
    ASSERT_FALSE(t.ok()) << s;
    EXPECT_NE(t.status().message().find("'" + std::string(s) + "'"), std::string::npos) << t.status().message();
  }
}

TEST(Photometric, SrgbCurveRoundTrips) {
  for (int v = 0; v < 256; ++v) EXPECT_EQ(LinearToSrgb(SrgbToLinear(static_cast<uint8_t>(v))), v);
  EXPECT_DOUBLE_EQ(SrgbToLinear(0), 0.0);
  EXPECT_DOUBLE_EQ(SrgbToLinear(255), 1.0);
  EXPECT_NEAR(SrgbToLinear(188), 0.5, 0.005);  // mid-grey in linear light
}

TEST(Photometric, EachTransformDoesWhatItSays) {
  const ColourImage im = Ramp();
  auto at = [](const ColourImage& i, int x, int y, int c) { return int{i.rgba[4 * (static_cast<size_t>(y) * i.width + x) + c]}; };
  // none: unchanged.
  EXPECT_EQ(ApplyPhotometric(Parse("none"), im, 0)->rgba, im.rgba);
  // exposure: twice the linear light (brighter, clipped at 255), half (darker); alpha kept.
  const ColourImage bright = *ApplyPhotometric(Parse("exposure:2"), im, 0);
  const ColourImage dark = *ApplyPhotometric(Parse("exposure:0.5"), im, 0);
  EXPECT_EQ(at(bright, 20, 10, 0), LinearToSrgb(2 * SrgbToLinear(80)));
  EXPECT_EQ(at(dark, 20, 10, 0), LinearToSrgb(0.5 * SrgbToLinear(80)));
  EXPECT_EQ(at(bright, 63, 47, 0), 255);
  EXPECT_EQ(at(bright, 0, 5, 3), 0);
  EXPECT_EQ(at(bright, 5, 5, 3), 255);
  // gamma on the stored values.
  EXPECT_EQ(at(*ApplyPhotometric(Parse("gamma:2"), im, 0), 32, 0, 0), std::lround(255 * std::pow(128 / 255.0, 2)));
  // white balance: each channel its own gain.
  const ColourImage warm = *ApplyPhotometric(Parse("white-balance:1.3,1,0.7"), im, 0);
  EXPECT_GT(at(warm, 20, 10, 0), 80);
  EXPECT_EQ(at(warm, 20, 10, 1), 50);
  EXPECT_LT(at(warm, 20, 10, 2), 60);
  // saturation 0: grey (every channel the luma); 1: unchanged.
  const ColourImage grey = *ApplyPhotometric(Parse("saturation:0"), im, 0);
  EXPECT_EQ(at(grey, 20, 10, 0), at(grey, 20, 10, 1));
  EXPECT_EQ(at(grey, 20, 10, 1), at(grey, 20, 10, 2));
  EXPECT_EQ(ApplyPhotometric(Parse("saturation:1"), im, 0)->rgba, im.rgba);
  // clip: nothing above 0.8 of the range.
  const ColourImage clipped = *ApplyPhotometric(Parse("clip:0.8"), im, 0);
  for (size_t i = 0; i < clipped.rgba.size(); i += 4)
    for (int c = 0; c < 3; ++c) EXPECT_LE(clipped.rgba[i + c], 204);
  // JPEG: close to the original, not equal; alpha kept.
  const ColourImage jpeg = *ApplyPhotometric(Parse("jpeg:30"), im, 0);
  double err = 0;
  for (size_t i = 0; i < jpeg.rgba.size(); i += 4)
    for (int c = 0; c < 3; ++c) err += std::fabs(double(jpeg.rgba[i + c]) - im.rgba[i + c]);
  err /= 3.0 * im.width * im.height;
  EXPECT_GT(err, 0.1);
  EXPECT_LT(err, 12);
  EXPECT_EQ(at(jpeg, 0, 5, 3), 0);
}

TEST(Photometric, NoiseHasItsSigmaAndIsTheSameForASeed) {
  ColourImage flat;
  flat.width = 200, flat.height = 100;
  flat.rgba.assign(4 * 200 * 100, 128);
  const PhotometricTransform t = Parse("noise:8");
  const ColourImage a = *ApplyPhotometric(t, flat, 1), b = *ApplyPhotometric(t, flat, 1), c = *ApplyPhotometric(t, flat, 2);
  EXPECT_EQ(a.rgba, b.rgba);
  EXPECT_NE(a.rgba, c.rgba);
  double sum = 0, sum2 = 0, n = 0;
  for (size_t i = 0; i < a.rgba.size(); i += 4)
    for (int ch = 0; ch < 3; ++ch) {
      const double d = double(a.rgba[i + ch]) - 128;
      sum += d, sum2 += d * d, ++n;
    }
  EXPECT_NEAR(sum / n, 0, 0.2);
  EXPECT_NEAR(std::sqrt(sum2 / n), 8, 0.3);
}

TEST(Photometric, RefusesAnInconsistentImage) {
  ColourImage bad;
  bad.width = 4, bad.height = 4;
  EXPECT_FALSE(ApplyPhotometric(Parse("gamma:2"), bad, 0).ok());
}

}  // namespace
}  // namespace mcpose::synth

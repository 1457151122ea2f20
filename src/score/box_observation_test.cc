#include "score/box_observation.h"

#include <gtest/gtest.h>

#include "score/colour.h"

namespace mcpose::score {
namespace {

ColourImage Image(int w, int h) {
  ColourImage im;
  im.width = w, im.height = h;
  im.rgba.resize(4 * static_cast<size_t>(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      uint8_t* p = im.rgba.data() + 4 * (static_cast<size_t>(y) * w + x);
      p[0] = static_cast<uint8_t>(10 * x), p[1] = static_cast<uint8_t>(10 * y), p[2] = static_cast<uint8_t>(100);
      p[3] = 255;
    }
  return im;
}

uint8_t Channel(uint32_t v, int c) { return static_cast<uint8_t>(v >> (8 * c)); }

TEST(ObservedColour, EachPixelIsTheMeanOfItsNeighbourhood) {
  const ColourImage im = Image(20, 16);
  const render::PixelRect rect{4, 3, 12, 11};
  // Radius 0: the pixels themselves, every stride-th.
  const std::vector<uint32_t> plain = ObservedColour(im, nullptr, rect, 2, 0, nullptr);
  ASSERT_EQ(plain.size(), 16u);  // 4 x 4 grid pixels
  EXPECT_EQ(Channel(plain[0], 0), 40);
  EXPECT_EQ(Channel(plain[0], 1), 30);
  EXPECT_EQ(Channel(plain[5], 0), 60);  // grid (1, 1) = image (6, 5)
  EXPECT_EQ(Channel(plain[5], 1), 50);
  // Radius 1: the 3 x 3 mean; a linear ramp's mean is its centre.
  const std::vector<uint32_t> smooth = ObservedColour(im, nullptr, rect, 1, 1, nullptr);
  EXPECT_EQ(Channel(smooth[0], 0), 40);
  EXPECT_EQ(Channel(smooth[0], 1), 30);
  // At the image's corner the neighbourhood is cut: the mean of the 2 x 2 that exist.
  const std::vector<uint32_t> corner = ObservedColour(im, nullptr, render::PixelRect{0, 0, 2, 2}, 1, 1, nullptr);
  EXPECT_EQ(Channel(corner[0], 0), 5);
  // The transform applies to the mean.
  const std::vector<uint32_t> hue = ObservedColour(im, nullptr, rect, 1, 1, IntensityHueOf);
  EXPECT_EQ(hue[0], IntensityHueOf(smooth[0]));
}

TEST(ObservedColour, ClippedAndUnknownPixelsAndTheirNeighboursAreUnknown) {
  ColourImage im = Image(20, 16);
  // A pixel without colour and one at 255.
  im.rgba[4 * (5 * 20 + 5) + 3] = 0;
  im.rgba[4 * (10 * 20 + 10) + 0] = 255;
  const render::PixelRect all{0, 0, 20, 16};
  std::vector<uint32_t> c = ObservedColour(im, nullptr, all, 1, 1, nullptr);
  auto known = [&](int x, int y) { return (c[static_cast<size_t>(y) * 20 + x] >> 24) >= kKnownAlpha; };
  EXPECT_FALSE(known(5, 5));
  EXPECT_FALSE(known(6, 4));  // a neighbour of it
  EXPECT_TRUE(known(7, 5));
  EXPECT_FALSE(known(10, 10));
  EXPECT_FALSE(known(9, 11));
  EXPECT_TRUE(known(12, 10));
  c = ObservedColour(im, nullptr, all, 1, 0, nullptr);
  EXPECT_TRUE(known(6, 4));
  EXPECT_FALSE(known(10, 10));

  // A saturated channel at a level below 255 (a tone curve clipped at 200): the box's brightest
  // value, shared by many of its pixels, is clipped; the same level on a few pixels is not.
  ColourImage sat = Image(20, 16);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 20; ++x) sat.rgba[4 * (y * 20 + x) + 1] = static_cast<uint8_t>(std::min(10 * y, 140));
  c = ObservedColour(sat, nullptr, all, 1, 0, nullptr);
  EXPECT_FALSE(known(3, 15));  // green at its clip level 140 (rows 14 and 15: 40 pixels)
  EXPECT_TRUE(known(3, 12));
  ColourImage few = Image(20, 16);
  few.rgba[4 * (2 * 20 + 2) + 1] = 250;  // one bright pixel: the maximum, but alone
  c = ObservedColour(few, nullptr, all, 1, 0, nullptr);
  EXPECT_TRUE(known(2, 2));
}

// Only the pixels on the same surface are averaged: at an object's edge the background behind
// it (another depth) gives no colour; a pixel without depth keeps its own colour.
TEST(ObservedColour, TheMeanTakesOnlyTheSameSurface) {
  ColourImage im = Image(20, 16);
  DepthImage depth;
  depth.width = 20, depth.height = 16;
  depth.depth_m.assign(20 * 16, 0.8f);
  for (int y = 0; y < 16; ++y)
    for (int x = 10; x < 20; ++x) depth.depth_m[static_cast<size_t>(y) * 20 + x] = 1.5f;  // the background
  depth.depth_m[3 * 20 + 3] = 0.f;  // no depth here
  const render::PixelRect all{0, 0, 20, 16};
  const std::vector<uint32_t> c = ObservedColour(im, &depth, all, 1, 1, nullptr);
  // x = 9 on the near surface: the mean of x = 8 and 9 (red 85), not of 8-10 (90).
  EXPECT_EQ(Channel(c[5 * 20 + 9], 0), 85);
  EXPECT_EQ(Channel(c[5 * 20 + 10], 0), 105);  // the background's edge: x = 10 and 11
  EXPECT_EQ(Channel(c[3 * 20 + 3], 0), 30);    // its own colour
  // Beside it, the eight neighbours with depth: (2 x 30 + 3 x 40 + 3 x 50) / 8, rounded.
  EXPECT_EQ(Channel(c[3 * 20 + 4], 0), 41);
  // Without depth, every neighbour.
  EXPECT_EQ(Channel(ObservedColour(im, nullptr, all, 1, 1, nullptr)[5 * 20 + 9], 0), 90);
}

}  // namespace
}  // namespace mcpose::score

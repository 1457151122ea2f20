#include "report/overlay.h"

#include <gtest/gtest.h>

#include "synthetic_mesh.h"

namespace mcpose::report {
namespace {

MaskImage Rect(int width, int height, int x0, int y0, int x1, int y1) {
  MaskImage m;
  m.width = width, m.height = height;
  m.values.assign(static_cast<size_t>(width) * height, 0);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) m.values[static_cast<size_t>(y) * width + x] = 255;
  return m;
}

ColourImage Blank(int width, int height, uint8_t grey) {
  ColourImage c;
  c.width = width, c.height = height;
  c.rgba.assign(4 * static_cast<size_t>(width) * height, grey);
  return c;
}

Rgba8 At(const ColourImage& c, int x, int y) {
  const uint8_t* p = c.at(x, y);
  return {p[0], p[1], p[2], p[3]};
}

TEST(Overlay, OutlineIsTheMaskBorderInsideTheImage) {
  const MaskImage outline = Outline(Rect(12, 10, 2, 3, 7, 8));  // 5 x 5 square
  int count = 0;
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 12; ++x) {
      const bool border = x >= 2 && x < 7 && y >= 3 && y < 8 && (x == 2 || x == 6 || y == 3 || y == 7);
      EXPECT_EQ(outline.at(x, y), border) << x << "," << y;
      count += outline.at(x, y);
    }
  EXPECT_EQ(count, 16);
  // A single pixel is its own outline; an empty mask has none.
  EXPECT_TRUE(Outline(Rect(5, 5, 2, 2, 3, 3)).at(2, 2));
  for (uint8_t v : Outline(Rect(5, 5, 0, 0, 0, 0)).values) EXPECT_EQ(v, 0);
}

TEST(Overlay, OutlineDrawsNoLineAlongTheImageBorder) {
  // The mask fills the bottom-left corner: only its top and right sides are outline.
  const MaskImage outline = Outline(Rect(10, 10, 0, 6, 4, 10));
  EXPECT_TRUE(outline.at(0, 6));
  EXPECT_TRUE(outline.at(3, 9));
  EXPECT_FALSE(outline.at(0, 8));  // on the left image border, inside
  EXPECT_FALSE(outline.at(1, 9));  // on the bottom image border, inside
  EXPECT_FALSE(outline.at(1, 8));
}

TEST(Overlay, DrawOutlinePaintsWithinTheRadiusOnly) {
  const MaskImage outline = Outline(Rect(40, 40, 10, 10, 30, 30));
  ColourImage image = Blank(40, 40, 0);
  OutlineStyle style;
  style.colour = {255, 0, 0, 255};
  style.radius_px = 1;
  DrawOutline(outline, style, &image);
  EXPECT_EQ(At(image, 10, 20), (Rgba8{255, 0, 0, 255}));  // on the outline
  EXPECT_EQ(At(image, 9, 20), (Rgba8{255, 0, 0, 255}));   // one pixel outside
  EXPECT_EQ(At(image, 11, 20), (Rgba8{255, 0, 0, 255}));  // one pixel inside
  EXPECT_EQ(At(image, 8, 20), (Rgba8{0, 0, 0, 0}));       // two away: untouched
  EXPECT_EQ(At(image, 20, 20), (Rgba8{0, 0, 0, 0}));
}

TEST(Overlay, DashedOutlineAlternatesTwoColours) {
  const MaskImage outline = Outline(Rect(64, 64, 4, 4, 60, 60));
  ColourImage image = Blank(64, 64, 0);
  OutlineStyle style;
  style.colour = {255, 255, 255, 255};
  style.dashed = true;
  style.dash_colour = {1, 2, 3, 255};
  style.dash_px = 4;
  style.radius_px = 0;
  DrawOutline(outline, style, &image);
  // Along the top side (y = 4): the colour switches every 4 pixels, 13 times from x = 4 to 59.
  int changes = 0;
  for (int x = 5; x < 60; ++x) changes += !(At(image, x, 4) == At(image, x - 1, 4));
  EXPECT_EQ(changes, 13);
  EXPECT_EQ(At(image, 4, 4), (Rgba8{255, 255, 255, 255}));  // block (1, 1): even sum
  EXPECT_EQ(At(image, 8, 4), (Rgba8{1, 2, 3, 255}));        // block (2, 1): odd sum
  EXPECT_EQ(At(image, 20, 20), (Rgba8{0, 0, 0, 0}));        // inside: untouched
}

TEST(Overlay, DivergingColourRunsBlueWhiteRed) {
  EXPECT_EQ(DivergingColour(-1), (Rgba8{33, 102, 172, 255}));
  EXPECT_EQ(DivergingColour(0), (Rgba8{247, 247, 247, 255}));
  EXPECT_EQ(DivergingColour(1), (Rgba8{178, 24, 43, 255}));
  EXPECT_EQ(DivergingColour(-5), DivergingColour(-1));  // clamped
  EXPECT_EQ(DivergingColour(7), DivergingColour(1));
  EXPECT_EQ(DivergingColour(NAN), DivergingColour(-1));
  const Rgba8 c = DivergingColour(0.25);  // halfway between white and the light red anchor
  EXPECT_EQ(c, (Rgba8{246, 206, 189, 255}));
  EXPECT_EQ(DivergingColourStops(),
            (std::vector<std::string>{"#2166ac", "#92c5de", "#f7f7f7", "#f4a582", "#b2182b"}));
}

// A cube of side 0.1 m one metre in front of the camera: its front face (z = 0.95 m) projects to
// u in cx +- 26.32 px, v in cy +- 26.32 px. With pixel centres at integer coordinates the
// silhouette covers columns 74..126 and rows 54..106 for cx = 100, cy = 80 (centres at
// half-integers would give 74..125 and 54..105).
TEST(Overlay, RenderDepthUsesIntegerPixelCentres) {
  Mesh cube;
  testing::AddBox(&cube, Eigen::Vector3f::Constant(-0.05f), Eigen::Vector3f::Constant(0.05f));
  Intrinsics K{500, 500, 100, 80, 200, 160};
  const DepthImage depth = RenderDepth(cube, SE3(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 1)), K);
  ASSERT_EQ(depth.width, 200);
  ASSERT_EQ(depth.height, 160);
  const MaskImage mask = Silhouette(depth);
  int x_min = 1000, x_max = -1, y_min = 1000, y_max = -1, covered = 0;
  for (int y = 0; y < 160; ++y)
    for (int x = 0; x < 200; ++x) {
      if (!mask.at(x, y)) {
        EXPECT_EQ(depth.at(x, y), 0.0f);
        continue;
      }
      ++covered;
      x_min = std::min(x_min, x), x_max = std::max(x_max, x), y_min = std::min(y_min, y), y_max = std::max(y_max, y);
      EXPECT_NEAR(depth.at(x, y), 0.95f, 1e-5f);  // the front face
    }
  EXPECT_EQ(x_min, 74);
  EXPECT_EQ(x_max, 126);
  EXPECT_EQ(y_min, 54);
  EXPECT_EQ(y_max, 106);
  EXPECT_EQ(covered, 53 * 53);
}

TEST(Overlay, DepthResidualColoursAndCountsTheRect) {
  const int w = 20, h = 10;
  DepthImage observed{w, h, std::vector<float>(static_cast<size_t>(w) * h, 1.0f)};
  DepthImage rendered{w, h, std::vector<float>(static_cast<size_t>(w) * h, 0.0f)};
  // Rendered in columns 4..11 of rows 2..7: the observed surface 20 mm behind in columns 4..7,
  // 4 mm in front in 8..9, and no observed depth in 10..11.
  for (int y = 2; y < 8; ++y)
    for (int x = 4; x < 12; ++x) {
      const size_t i = static_cast<size_t>(y) * w + x;
      rendered.depth_m[i] = x < 8 ? 0.98f : 1.004f;
      if (x >= 10) observed.depth_m[i] = 0;
    }
  const ColourImage colour = Blank(w, h, 200);
  ResidualStats stats;
  const ColourImage out =
      DepthResidualImage(observed, rendered, colour, render::PixelRect{2, 1, 14, 9}, 0.02, 0.01, &stats);
  ASSERT_EQ(out.width, 12);
  ASSERT_EQ(out.height, 8);
  EXPECT_EQ(At(out, 4 - 2, 3 - 1), DivergingColour(1));      // +20 mm: red end
  EXPECT_EQ(At(out, 8 - 2, 3 - 1), DivergingColour(-0.2));  // -4 mm
  EXPECT_EQ(At(out, 10 - 2, 3 - 1), (Rgba8{0, 0, 0, 255}));  // no observed depth
  EXPECT_EQ(At(out, 0, 0), (Rgba8{164, 164, 164, 255}));     // not rendered: 64 + 200 / 2
  EXPECT_EQ(stats.rendered_pixels, 6 * 8);
  EXPECT_EQ(stats.compared_pixels, 6 * 6);
  EXPECT_NEAR(stats.median_abs_mm, 20, 1e-3);  // 24 pixels at 20 mm, 12 at 4 mm
  EXPECT_NEAR(stats.inlier_share, 12.0 / 36, 1e-12);
}

TEST(Overlay, DepthAsColourIsBrightNearDarkFarBlackMissing) {
  DepthImage d{3, 1, {0.5f, 1.5f, 0.0f}};
  const ColourImage c = DepthAsColour(d);
  EXPECT_EQ(At(c, 0, 0), (Rgba8{255, 255, 255, 255}));
  EXPECT_EQ(At(c, 1, 0), (Rgba8{40, 40, 40, 255}));
  EXPECT_EQ(At(c, 2, 0), (Rgba8{0, 0, 0, 255}));
}

}  // namespace
}  // namespace mcpose::report

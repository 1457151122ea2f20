#include "report/svg.h"

#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace mcpose::report {
namespace {

// Occurrences of `needle` in `text`.
int Count(const std::string& text, const std::string& needle) {
  int n = 0;
  for (size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) ++n;
  return n;
}

// Whether every element of `xml` is closed in order and no attribute value holds a raw '<'
// (a small well-formedness check: enough for markup that escapes its text).
bool Balanced(const std::string& xml) {
  std::vector<std::string> open;
  size_t i = 0;
  while ((i = xml.find('<', i)) != std::string::npos) {
    const size_t end = xml.find('>', i);
    if (end == std::string::npos) return false;
    const std::string tag = xml.substr(i + 1, end - i - 1);
    if (tag.find('<') != std::string::npos) return false;
    if (tag.front() == '/') {
      if (open.empty() || open.back() != tag.substr(1)) return false;
      open.pop_back();
    } else if (tag.back() != '/') {
      open.push_back(tag.substr(0, tag.find(' ')));
    }
    i = end + 1;
  }
  return open.empty();
}

TEST(Svg, EscapeXmlReplacesMarkupCharacters) {
  EXPECT_EQ(EscapeXml("a<b>&\"c'"), "a&lt;b&gt;&amp;&quot;c&#39;");
  EXPECT_EQ(EscapeXml("plain 003_cracker_box"), "plain 003_cracker_box");
}

TEST(Svg, NiceTicksUseStepsOfOneTwoOrFive) {
  EXPECT_EQ(NiceTicks(0, 10, 6), (std::vector<double>{0, 2, 4, 6, 8, 10}));
  EXPECT_EQ(NiceTicks(-20, 20, 5), (std::vector<double>{-20, -10, 0, 10, 20}));
  EXPECT_EQ(NiceTicks(0, 100, 6), (std::vector<double>{0, 20, 40, 60, 80, 100}));
  const std::vector<double> t = NiceTicks(0.13, 0.91, 5);  // step 0.2: 0.2 .. 0.8
  ASSERT_EQ(t.size(), 4u);
  EXPECT_NEAR(t.front(), 0.2, 1e-12);
  EXPECT_NEAR(t.back(), 0.8, 1e-12);
  EXPECT_TRUE(NiceTicks(1, 1, 5).empty());
  EXPECT_TRUE(NiceTicks(0, NAN, 5).empty());
}

TEST(Svg, LinePlotMapsDataIntoTheFrameAndEscapesText) {
  LinePlot p;
  p.id = "p1";
  p.width_px = 300, p.height_px = 200;
  p.title = "weights <per> iteration";
  p.x_min = 0, p.x_max = 10, p.y_min = 0, p.y_max = 1;
  p.series.push_back({"best & mean", "#c62828", {{0, 1}, {10, 0}}, 2, false, true});
  p.series.push_back({"hidden", "#000", {{5, 0.5}}, 1, true, false});
  p.series.push_back({"empty", "#111", {}, 1, false, true});
  p.y_rules.push_back({0.85, "tau 0.85"});
  const std::string svg = LinePlotSvg(p);
  EXPECT_TRUE(Balanced(svg)) << svg;
  // Margins 46 left, 10 right, 22 top, 36 bottom: (0, 1) is the frame's top-left corner and
  // (10, 0) its bottom-right one.
  EXPECT_NE(svg.find("points=\"46.0,22.0 290.0,164.0\""), std::string::npos) << svg;
  EXPECT_EQ(Count(svg, "<polyline"), 2);  // the empty series draws nothing
  EXPECT_EQ(Count(svg, "stroke-dasharray=\"5 3\""), 1);
  EXPECT_NE(svg.find("weights &lt;per&gt; iteration"), std::string::npos);
  EXPECT_NE(svg.find(">best &amp; mean</text>"), std::string::npos);  // in the legend
  EXPECT_EQ(svg.find(">hidden</text>"), std::string::npos);             // not in it
  EXPECT_NE(svg.find(">empty</text>"), std::string::npos);
  EXPECT_NE(svg.find("clip-path=\"url(#p1-clip)\""), std::string::npos);
  EXPECT_NE(svg.find(">tau 0.85</text>"), std::string::npos);
  for (const char* tick : {">0</text>", ">2</text>", ">10</text>", ">0.2</text>", ">1</text>"})
    EXPECT_NE(svg.find(tick), std::string::npos) << tick;
}

TEST(Svg, IntegerAxisDropsFractionalTicks) {
  LinePlot p;
  p.id = "p2";
  p.x_min = 1, p.x_max = 3;
  p.x_integer = true;
  const std::string svg = LinePlotSvg(p);
  EXPECT_NE(svg.find(">2</text>"), std::string::npos);
  EXPECT_EQ(svg.find(">1.5</text>"), std::string::npos);
  EXPECT_EQ(svg.find(">1.2</text>"), std::string::npos);
}

TEST(Svg, ColourBarHasTheStopsInOrderAndLabelledTicks) {
  const std::string svg = ColourBarSvg("bar", {"#0000ff", "#ffffff", "#ff0000"}, 20, "mm", 210);
  EXPECT_TRUE(Balanced(svg)) << svg;
  const size_t blue = svg.find("offset=\"0.0%\" stop-color=\"#0000ff\"");
  const size_t white = svg.find("offset=\"50.0%\" stop-color=\"#ffffff\"");
  const size_t red = svg.find("offset=\"100.0%\" stop-color=\"#ff0000\"");
  ASSERT_NE(blue, std::string::npos);
  ASSERT_NE(white, std::string::npos);
  ASSERT_NE(red, std::string::npos);
  EXPECT_LT(blue, white);
  EXPECT_LT(white, red);
  EXPECT_NE(svg.find("fill=\"url(#bar)\""), std::string::npos);
  for (const char* tick : {">-20</text>", ">-10</text>", ">0</text>", ">10</text>", ">20 mm</text>"})
    EXPECT_NE(svg.find(tick), std::string::npos) << tick;
}

}  // namespace
}  // namespace mcpose::report

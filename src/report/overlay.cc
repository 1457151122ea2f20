#include "report/overlay.h"

#include <algorithm>
#include <array>
#include <cstdio>

#include "core/check.h"

namespace mcpose::report {
namespace {

// ColorBrewer's RdBu anchors, blue (-1) to red (+1); the map interpolates linearly between
// them, as an SVG gradient over the same stops does.
constexpr std::array<std::array<uint8_t, 3>, 5> kDivergingAnchors = {{
    {33, 102, 172}, {146, 197, 222}, {247, 247, 247}, {244, 165, 130}, {178, 24, 43}}};

uint8_t Grey(const uint8_t* rgba) {
  return static_cast<uint8_t>((299 * rgba[0] + 587 * rgba[1] + 114 * rgba[2] + 500) / 1000);
}

void Put(ColourImage* image, int x, int y, Rgba8 c) {
  uint8_t* q = image->rgba.data() + 4 * (static_cast<size_t>(y) * image->width + x);
  q[0] = c.r, q[1] = c.g, q[2] = c.b, q[3] = 255;
}

}  // namespace

MaskImage Silhouette(const DepthImage& rendered) {
  MaskImage mask;
  mask.width = rendered.width, mask.height = rendered.height;
  mask.values.resize(rendered.depth_m.size());
  for (size_t i = 0; i < rendered.depth_m.size(); ++i) mask.values[i] = rendered.depth_m[i] > 0 ? 255 : 0;
  return mask;
}

MaskImage Outline(const MaskImage& mask) {
  MaskImage out;
  out.width = mask.width, out.height = mask.height;
  out.values.assign(mask.values.size(), 0);
  const auto outside = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < mask.width && y < mask.height && !mask.at(x, y);
  };
  for (int y = 0; y < mask.height; ++y)
    for (int x = 0; x < mask.width; ++x)
      if (mask.at(x, y) && (outside(x - 1, y) || outside(x + 1, y) || outside(x, y - 1) || outside(x, y + 1)))
        out.values[static_cast<size_t>(y) * mask.width + x] = 255;
  return out;
}

void DrawOutline(const MaskImage& outline, const OutlineStyle& style, ColourImage* image) {
  MCPOSE_CHECK(outline.width == image->width && outline.height == image->height);
  const int r = std::max(0, style.radius_px), dash = std::max(1, style.dash_px);
  // Which pixels to paint first, so the dash colour of a pixel depends on where it is only.
  std::vector<uint8_t> paint(outline.values.size(), 0);
  for (int y = 0; y < outline.height; ++y)
    for (int x = 0; x < outline.width; ++x) {
      if (!outline.at(x, y)) continue;
      for (int yy = std::max(0, y - r); yy <= std::min(outline.height - 1, y + r); ++yy)
        for (int xx = std::max(0, x - r); xx <= std::min(outline.width - 1, x + r); ++xx)
          paint[static_cast<size_t>(yy) * outline.width + xx] = 1;
    }
  for (int y = 0; y < outline.height; ++y)
    for (int x = 0; x < outline.width; ++x) {
      if (!paint[static_cast<size_t>(y) * outline.width + x]) continue;
      // Blocks of dash x dash pixels in a checkerboard: a line in any direction crosses them
      // one after another.
      const bool second = style.dashed && ((x / dash + y / dash) % 2 == 1);
      Put(image, x, y, second ? style.dash_colour : style.colour);
    }
}

Rgba8 DivergingColour(double t) {
  if (!(t >= -1)) t = -1;  // NaN too
  if (t > 1) t = 1;
  const double pos = (t + 1) / 2 * (kDivergingAnchors.size() - 1);
  const size_t i = std::min(static_cast<size_t>(pos), kDivergingAnchors.size() - 2);
  const double f = pos - static_cast<double>(i);
  const auto mix = [&](int c) {
    return static_cast<uint8_t>(std::lround((1 - f) * kDivergingAnchors[i][c] + f * kDivergingAnchors[i + 1][c]));
  };
  return {mix(0), mix(1), mix(2), 255};
}

std::vector<std::string> DivergingColourStops() {
  std::vector<std::string> stops;
  for (const auto& a : kDivergingAnchors) {
    char buffer[8];
    std::snprintf(buffer, sizeof buffer, "#%02x%02x%02x", a[0], a[1], a[2]);
    stops.push_back(buffer);
  }
  return stops;
}

ColourImage DepthResidualImage(const DepthImage& observed, const DepthImage& rendered, const ColourImage& colour,
                               const render::PixelRect& rect, double limit_m, double inlier_m,
                               ResidualStats* stats) {
  MCPOSE_CHECK(rect.x0 >= 0 && rect.y0 >= 0 && rect.x1 <= observed.width && rect.y1 <= observed.height);
  MCPOSE_CHECK(rendered.width == observed.width && colour.width == observed.width);
  ColourImage out;
  out.width = std::max(0, rect.width()), out.height = std::max(0, rect.height());
  out.rgba.assign(4 * static_cast<size_t>(out.width) * out.height, 255);
  std::vector<float> abs_residual;
  int rendered_pixels = 0, inliers = 0;
  for (int y = rect.y0; y < rect.y1; ++y)
    for (int x = rect.x0; x < rect.x1; ++x) {
      const float z_r = rendered.at(x, y), z_o = observed.at(x, y);
      Rgba8 c;
      if (z_r > 0 && z_o > 0) {
        const double residual = static_cast<double>(z_o) - z_r;
        c = DivergingColour(residual / limit_m);
        abs_residual.push_back(static_cast<float>(std::fabs(residual)));
        inliers += std::fabs(residual) < inlier_m;
      } else if (z_r > 0) {
        c = {0, 0, 0, 255};
      } else {
        // Context: the frame in grey, dimmed so that the map's light colours stand out.
        const uint8_t g = static_cast<uint8_t>(64 + Grey(colour.at(x, y)) / 2);
        c = {g, g, g, 255};
      }
      rendered_pixels += z_r > 0;
      Put(&out, x - rect.x0, y - rect.y0, c);
    }
  if (stats) {
    *stats = ResidualStats{};
    stats->rendered_pixels = rendered_pixels;
    stats->compared_pixels = static_cast<int>(abs_residual.size());
    if (!abs_residual.empty()) {
      const auto mid = abs_residual.begin() + static_cast<std::ptrdiff_t>(abs_residual.size() / 2);
      std::nth_element(abs_residual.begin(), mid, abs_residual.end());
      stats->median_abs_mm = 1000.0 * *mid;
      stats->inlier_share = static_cast<double>(inliers) / static_cast<double>(abs_residual.size());
    }
  }
  return out;
}

ColourImage DepthAsColour(const DepthImage& depth) {
  ColourImage out;
  out.width = depth.width, out.height = depth.height;
  out.rgba.assign(4 * depth.depth_m.size(), 255);
  float lo = INFINITY, hi = 0;
  for (float z : depth.depth_m)
    if (z > 0) lo = std::min(lo, z), hi = std::max(hi, z);
  for (int y = 0; y < depth.height; ++y)
    for (int x = 0; x < depth.width; ++x) {
      const float z = depth.at(x, y);
      uint8_t g = 0;
      if (z > 0) g = static_cast<uint8_t>(std::lround(hi > lo ? 40 + 215 * (hi - z) / (hi - lo) : 255));
      Put(&out, x, y, {g, g, g, 255});
    }
  return out;
}

}  // namespace mcpose::report

#include "score/box_observation.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/check.h"

namespace mcpose::score {

BoxObservation DistributeBox(const DepthImage& depth, const Intrinsics& K, const render::PixelRect& rect,
                             double score, InlierMode mode, int stride, const ColourImage* colour,
                             uint32_t (*transform)(uint32_t), int smooth_radius, bool drop_clipped) {
  MCPOSE_CHECK_GE(stride, 1);
  BoxObservation b;
  b.image_rect = rect;
  b.stride = stride;
  const int gw = (rect.width() + stride - 1) / stride, gh = (rect.height() + stride - 1) / stride;
  b.rect = render::PixelRect{rect.x0, rect.y0, rect.x0 + gw, rect.y0 + gh};
  // Grid coordinate u_g = x0 + (u - x0) / s: the same projection, scaled about the box corner.
  b.K_grid = K;
  b.K_grid.fx = K.fx / stride;
  b.K_grid.fy = K.fy / stride;
  b.K_grid.cx = rect.x0 + (K.cx - rect.x0) / stride;
  b.K_grid.cy = rect.y0 + (K.cy - rect.y0) / stride;
  b.score = score;
  b.observed.resize(static_cast<size_t>(b.rect.area()));
  for (int j = 0; j < gh; ++j) {
    const float* src = depth.depth_m.data() + static_cast<size_t>(rect.y0 + j * stride) * depth.width + rect.x0;
    float* dst = b.observed.data() + static_cast<size_t>(j) * gw;
    for (int i = 0; i < gw; ++i) dst[i] = src[static_cast<size_t>(i) * stride];
  }
  if (colour) {
    MCPOSE_CHECK(colour->width == depth.width && colour->height == depth.height);
    b.observed_rgba = ObservedColour(*colour, &depth, rect, stride, smooth_radius, transform, drop_clipped);
  }
  b.n_observed = CountObserved(b.observed);
  b.observed_or_nan = ObservedOrNaN(b.observed);
  if (mode == InlierMode::k3D) b.cloud = std::make_unique<ObservedCloud>(b.K_grid, b.rect, b.observed);
  return b;
}

std::vector<uint32_t> ObservedColour(const ColourImage& image, const DepthImage* depth, const render::PixelRect& rect,
                                     int stride, int radius, uint32_t (*transform)(uint32_t), bool drop_clipped) {
  MCPOSE_CHECK_GE(stride, 1);
  MCPOSE_CHECK_GE(radius, 0);
  MCPOSE_CHECK(rect.x0 >= 0 && rect.y0 >= 0 && rect.x1 <= image.width && rect.y1 <= image.height);
  MCPOSE_CHECK(!depth || (depth->width == image.width && depth->height == image.height));
  const auto z_at = [depth, &image](int x, int y) {
    return depth ? depth->depth_m[static_cast<size_t>(y) * image.width + x] : 1.f;
  };
  // ---- Saturation: per channel, the box's brightest value, where many pixels share it -----
  std::array<int, 3> top{0, 0, 0};
  std::array<int64_t, 3> at_top{0, 0, 0};
  int64_t pixels = 0;
  for (int y = rect.y0; y < rect.y1; ++y)
    for (int x = rect.x0; x < rect.x1; ++x) {
      const uint8_t* p = image.at(x, y);
      if (p[3] == 0) continue;
      ++pixels;
      for (int c = 0; c < 3; ++c) {
        if (p[c] > top[c]) top[c] = p[c], at_top[c] = 0;
        if (p[c] == top[c]) ++at_top[c];
      }
    }
  std::array<int, 3> clip{256, 256, 256};  // nothing reaches 256: no pixel dropped
  if (drop_clipped) clip = {255, 255, 255};
  for (int c = 0; drop_clipped && c < 3; ++c)
    if (top[c] >= 128 && at_top[c] > 1 && static_cast<double>(at_top[c]) >= kClippedShare * static_cast<double>(pixels))
      clip[c] = top[c];

  // ---- Each grid pixel: the mean of its neighbourhood, unknown if any of it is ------------
  const int gw = (rect.width() + stride - 1) / stride, gh = (rect.height() + stride - 1) / stride;
  std::vector<uint32_t> out(static_cast<size_t>(gw) * gh, 0u);
  for (int j = 0; j < gh; ++j) {
    const int y = rect.y0 + j * stride;
    for (int i = 0; i < gw; ++i) {
      const int x = rect.x0 + i * stride;
      int sum[3] = {0, 0, 0}, n = 0;
      bool known = true;
      const float z = z_at(x, y);
      const int r = z > 0.f ? radius : 0;
      for (int yy = std::max(y - r, 0); known && yy <= std::min(y + r, image.height - 1); ++yy)
        for (int xx = std::max(x - r, 0); xx <= std::min(x + r, image.width - 1); ++xx) {
          if (r > 0 && !(std::fabs(z_at(xx, yy) - z) < kSameSurfaceM)) continue;  // another surface
          const uint8_t* p = image.at(xx, yy);
          if (p[3] == 0 || p[0] >= clip[0] || p[1] >= clip[1] || p[2] >= clip[2]) {
            known = false;
            break;
          }
          for (int c = 0; c < 3; ++c) sum[c] += p[c];
          ++n;
        }
      if (!known) continue;
      uint32_t rgba = 0xff000000u;
      for (int c = 0; c < 3; ++c) rgba |= static_cast<uint32_t>((sum[c] + n / 2) / n) << (8 * c);
      out[static_cast<size_t>(j) * gw + i] = transform ? transform(rgba) : rgba;
    }
  }
  return out;
}

void AddDepthBounds(BoxObservation* box, float eps_m) {
  const std::vector<int32_t> d = hw::ObservedDepthUnits(box->observed);
  const int32_t eps = hw::EpsUnits(eps_m);
  box->depth_bounds.resize(d.size());
  for (size_t i = 0; i < d.size(); ++i) box->depth_bounds[i] = hw::InlierBounds(d[i], eps);
}

hw::Camera BoxHardwareCamera(const BoxObservation& box) {
  const render::RasterParams p = BoxRasterParams(box, /*cull_backfaces=*/true);
  return hw::QuantizeCamera(p.fx, p.fy, p.cx, p.cy, p.box.x0, p.box.y0, p.box.width(), p.box.height(), p.z_near_m);
}

render::RasterParams BoxRasterParams(const BoxObservation& box, bool cull_backfaces) {
  render::RasterParams params;
  params.fx = static_cast<float>(box.K_grid.fx);
  params.fy = static_cast<float>(box.K_grid.fy);
  params.cx = static_cast<float>(box.K_grid.cx);
  params.cy = static_cast<float>(box.K_grid.cy);
  params.box = box.rect;
  params.cull_backfaces = cull_backfaces;
  return params;
}

}  // namespace mcpose::score

#include "score/box_observation.h"

#include "core/check.h"

namespace mcpose::score {

BoxObservation DistributeBox(const DepthImage& depth, const Intrinsics& K, const render::PixelRect& rect,
                             double score, InlierMode mode, int stride, const ColourImage* colour,
                             uint32_t (*transform)(uint32_t)) {
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
    b.observed_rgba.resize(b.observed.size());
    for (int j = 0; j < gh; ++j)
      for (int i = 0; i < gw; ++i) {
        const uint8_t* p = colour->at(rect.x0 + i * stride, rect.y0 + j * stride);
        const uint32_t rgba = uint32_t{p[0]} | (uint32_t{p[1]} << 8) | (uint32_t{p[2]} << 16) | (uint32_t{p[3]} << 24);
        b.observed_rgba[static_cast<size_t>(j) * gw + i] = transform ? transform(rgba) : rgba;
      }
  }
  b.n_observed = CountObserved(b.observed);
  b.observed_or_nan = ObservedOrNaN(b.observed);
  if (mode == InlierMode::k3D) b.cloud = std::make_unique<ObservedCloud>(b.K_grid, b.rect, b.observed);
  return b;
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

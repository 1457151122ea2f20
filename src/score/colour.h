// The colour test of one rendered hypothesis: over its depth inliers, the model's colour at the
// surface point each pixel shows against the observed colour there.
//
// Deferred: the raster cores render depth only; for every depth-inlier pixel the kernel
// back-projects the rendered depth to the camera point it shows, maps it into the model frame
// and reads the model's colour there from a model-space grid (score/colour_grid.h, baked
// from a texture or vertex colours). The colour's resolution is that grid's, whatever mesh
// level rendered the depth.
//
// What is summed are exact integers, so the SIMD kernel (colour_simd.cc) gives the same sums as
// the scalar reference (colour.cc) on every target.
#pragma once

#include <cstdint>

#include "render/raster.h"

namespace mcpose::score {

// A model's colour grid as the kernels read it. Cell (i, j, k) covers
// origin + cell_m * ([i, i + 1) x [j, j + 1) x [k, k + 1)); cells[(k * ny + j) * nx + i] is
// RGBA8 packed little-endian (red in the low byte). Alpha below 128 means unknown.
struct ColourLookup {
  const uint32_t* cells = nullptr;
  int nx = 0, ny = 0, nz = 0;
  float origin[3] = {0, 0, 0};  // model frame, metres
  float inv_cell = 0;           // 1 / cell_m
};

inline constexpr uint32_t kKnownAlpha = 128;

// Normalised colour of a packed RGBA8 pixel: each channel times 255 / (r + g + b), so that a
// darker or brighter light on the same surface gives the same value; unknown (alpha 0) where
// r + g + b < kMinChromaSum (too dark for its hue to mean anything) or alpha is below
// kKnownAlpha.
inline constexpr uint32_t kMinChromaSum = 30;
// Intensity and hue of a packed RGBA8 pixel, as three channels: (r + g + b) / 3, and red and
// green times 255 / (r + g + b) (grey, 85, where r + g + b < kMinChromaSum); alpha kept.
inline uint32_t IntensityHueOf(uint32_t rgba) {
  const uint32_t r = rgba & 0xff, g = (rgba >> 8) & 0xff, b = (rgba >> 16) & 0xff;
  const uint32_t sum = r + g + b;
  const uint32_t i = (sum + 1) / 3;
  const uint32_t cr = sum < kMinChromaSum ? 85 : (255 * r + sum / 2) / sum;
  const uint32_t cg = sum < kMinChromaSum ? 85 : (255 * g + sum / 2) / sum;
  return i | (cr << 8) | (cg << 16) | (rgba & 0xff000000u);
}
inline uint32_t ChromaOf(uint32_t rgba) {
  const uint32_t r = rgba & 0xff, g = (rgba >> 8) & 0xff, b = (rgba >> 16) & 0xff;
  const uint32_t sum = r + g + b;
  if ((rgba >> 24) < kKnownAlpha || sum < kMinChromaSum) return 0;
  auto norm = [sum](uint32_t c) { return (255 * c + sum / 2) / sum; };
  return norm(r) | (norm(g) << 8) | (norm(b) << 16) | (rgba & 0xff000000u);
}

// Sums over the pixels counted, per channel (red, green, blue): model m, observed o.
struct ColourStats {
  int64_t n = 0;
  int64_t m[3] = {0, 0, 0}, o[3] = {0, 0, 0};
  int64_t mm[3] = {0, 0, 0}, oo[3] = {0, 0, 0}, mo[3] = {0, 0, 0};
  bool operator==(const ColourStats&) const = default;
};

// One sample in one box. Box-relative pixel (x, y) of the grid sits at grid pixel
// (grid_x0 + x, grid_y0 + y), which looks along ((u - cx) * inv_fx, (v - cy) * inv_fy, 1).
struct ColourSample {
  const float* rendered = nullptr;         // the sample's z-buffer, +inf where nothing was drawn
  const float* observed = nullptr;         // observed depth, 0 where invalid (reference)
  const float* observed_or_nan = nullptr;  // the same with NaN where invalid (SIMD)
  const uint32_t* observed_rgba = nullptr; // observed colour, RGBA8 packed; alpha 0: none
  int stride = 0;                          // row stride of the three, pixels
  render::PixelRect rect;                  // box-relative pixels to test (nothing drawn outside)
  float eps_m = 0.01f;                     // the depth-inlier threshold
  int step = 1;                            // test the pixels with x and y multiples of this (1-4)
  float grid_x0 = 0, grid_y0 = 0, cx = 0, cy = 0, inv_fx = 0, inv_fy = 0;
  float R_model_cam[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};  // row-major
  float t_model_cam[3] = {0, 0, 0};                     // p_model = R p_cam + t
};

// Counts pixel (x, y) of the rect, x and y multiples of `step`, when it is a depth inlier (drawn,
// observed depth valid, |z_r - z_o| < eps), its observed colour is there and its model colour is
// known: the reference, a pixel at a time, in the order the SIMD kernel's float operations
// follow.
ColourStats CountColour(const ColourSample& sample, const ColourLookup& lookup);
// The same sums a Highway vector of pixels at a time (colour_simd.cc, dispatched at run time).
ColourStats CountColourSimd(const ColourSample& sample, const ColourLookup& lookup);

// The colour agreement A of a sample in [0, 1]: (1 + r) / 2, r the mean over the channels of
// the correlation of model and observed colour over the counted pixels (so a gain or an offset of
// the light in the frame does not change it); a channel whose model or observed standard
// deviation is under 2 levels does not count. kNeutralAgreement when fewer than `min_pixels`
// pixels were counted or no channel varies.
//
// Hue first (`hue_first_levels` > 0, for intensity-hue statistics: channel 0 the intensity,
// 1 and 2 the hue): where a hue channel of the model varies with a standard deviation of at least
// `hue_first_levels`, r is the mean over the hue channels alone; elsewhere the intensity's
// alone. Shading changes the intensity of a curved surface, not its hue: where the surface has a
// coloured pattern its hue tells it, unmisled by the light; an achromatic surface (black print on
// white) has only its intensity, its hue being noise.
inline constexpr double kNeutralAgreement = 0.5;
double ColourAgreement(const ColourStats& stats, int min_pixels, double hue_first_levels = 0);


}  // namespace mcpose::score

// The depth distributor: one box's observed depth (and colour, when the colour term is used),
// cut out of the frame once and shared by every raster core and every iteration.
//
// Pixel stride s: the box is scored on a grid of every s-th image pixel in x and y, starting at
// its top-left pixel. The raster cores render into that grid as into a smaller image, through
// `K_grid`, whose pixel (x0 + i, y0 + j) is centred on image pixel (x0 + s i, y0 + s j): the
// same rays, s^2 times fewer of them. At s = 1, rect = image_rect and K_grid = the camera.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "hw/raster_core.h"
#include "mcpose/camera.h"
#include "mcpose/image.h"
#include "mcpose/options.h"
#include "render/raster.h"
#include "score/inlier.h"

namespace mcpose::score {

struct BoxObservation {
  render::PixelRect rect;        // the raster rect, grid pixels
  render::PixelRect image_rect;  // the box in image pixels
  int stride = 1;
  Intrinsics K_grid;             // projection onto the grid (fx / s, fy / s, shifted centre)
  std::vector<float> observed;         // rect-sized, metres, 0 = invalid
  std::vector<float> observed_or_nan;  // the same with NaN where invalid (the SIMD counter)
  int32_t n_observed = 0;              // N_b
  double score = 0;                    // detector confidence
  std::unique_ptr<ObservedCloud> cloud;  // only for InlierMode::k3D
  // Rect-sized observed colour, RGBA8 packed (red in the low byte), or empty without colour.
  std::vector<uint32_t> observed_rgba;
  // The hardware depth distributor's words (hw/raster_core.h), rect-sized: only for the engine
  // backend hw (AddDepthBounds).
  std::vector<hw::DepthBounds> depth_bounds;
};

// Sets box->depth_bounds from its observed depth for the inlier threshold eps_m.
void AddDepthBounds(BoxObservation* box, float eps_m);

// The BoxObservation of `rect` (image pixels, inside the image) at pixel stride `stride` >= 1,
// with the colour of `colour` (same size as `depth`) when it is given (ObservedColour), each
// pixel passed through `transform` (ChromaOf, IntensityHueOf) when that is given.
BoxObservation DistributeBox(const DepthImage& depth, const Intrinsics& K, const render::PixelRect& rect,
                             double score, InlierMode mode, int stride = 1, const ColourImage* colour = nullptr,
                             uint32_t (*transform)(uint32_t) = nullptr, int smooth_radius = 0,
                             bool drop_clipped = false);

// The observed colour of a box's grid pixels (rect-sized, row-major, RGBA8 packed): each the
// mean of the image pixels within smooth_radius of it (cut at the image's edges) that lie on the
// same surface, their observed depth within kSameSurfaceM of its own (all of them without
// `depth`; the pixel alone where it has no depth), passed through `transform` (may be null): the
// edge of an object takes no colour from what lies behind it. Unknown (alpha 0) where one of
// those pixels has no colour (alpha 0) or is clipped: a channel at 255, or at the box's brightest
// value of that channel when that is at least 128 and shared by at least kClippedShare of the
// box's pixels (a sensor or a tone curve saturated there, at whatever level), when
// `drop_clipped`: a clipped pixel's hue is wrong.
inline constexpr double kClippedShare = 0.005;
inline constexpr float kSameSurfaceM = 0.01f;
std::vector<uint32_t> ObservedColour(const ColourImage& colour, const DepthImage* depth, const render::PixelRect& rect,
                                     int stride, int smooth_radius, uint32_t (*transform)(uint32_t),
                                     bool drop_clipped = true);

// The raster-core parameters of a box: its grid projection and rect.
render::RasterParams BoxRasterParams(const BoxObservation& box, bool cull_backfaces);
// The same in the hardware core's formats (hw::QuantizeCamera of BoxRasterParams).
hw::Camera BoxHardwareCamera(const BoxObservation& box);

}  // namespace mcpose::score

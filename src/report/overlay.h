// What the report draws on a frame: a pose's rendered depth over the whole image, its
// silhouette and outline, outlines painted onto the colour image, and the depth residual of
// an estimate as a diverging colour map.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "mcpose/camera.h"
#include "mcpose/image.h"
#include "mcpose/mesh.h"
#include "mcpose/se3.h"
#include "render/depth_image.h"
#include "render/raster.h"

namespace mcpose::report {

// A pose's depth over the whole image: render::RenderDepth (render/depth_image.h).
using render::RenderDepth;

// The pixels a rendering covers (depth > 0), as 255.
MaskImage Silhouette(const DepthImage& rendered);

// The mask pixels with a 4-neighbour outside the mask. Neighbours beyond the image border do
// not count, so an object cut by the border gets no line along it.
MaskImage Outline(const MaskImage& mask);

struct OutlineStyle {
  Rgba8 colour{255, 255, 255, 255};
  // Dashed: the line alternates between `colour` and `dash_colour` in blocks of dash_px pixels
  // (two colours keep it visible on any background).
  bool dashed = false;
  Rgba8 dash_colour{0, 0, 0, 255};
  int dash_px = 4;
  int radius_px = 1;  // every pixel within this Chebyshev distance of the outline is painted
};

// Paints `outline` (same size as *image) onto *image in `style`.
void DrawOutline(const MaskImage& outline, const OutlineStyle& style, ColourImage* image);

// The diverging colour map of the depth residual: t in [-1, 1] (clamped) from blue through
// white (0) to red, and the same map as CSS colours for its colour bar.
Rgba8 DivergingColour(double t);
std::vector<std::string> DivergingColourStops();

struct ResidualStats {
  int rendered_pixels = 0;    // in the rect
  int compared_pixels = 0;    // rendered with an observed depth
  double median_abs_mm = NAN;  // of |observed - rendered| over the compared pixels
  double inlier_share = NAN;   // share of compared pixels with |observed - rendered| < inlier_m
};

// The rect of the frame as an image: where the pose renders and the sensor has a depth, the
// residual observed - rendered as DivergingColour(residual / limit_m) (red: the observed
// surface lies behind the model, blue: in front of it); where it renders without an observed
// depth, black; elsewhere the colour frame's grey value, dimmed. `rect` must lie in the image.
// Fills *stats when it is not null.
ColourImage DepthResidualImage(const DepthImage& observed, const DepthImage& rendered, const ColourImage& colour,
                               const render::PixelRect& rect, double limit_m, double inlier_m,
                               ResidualStats* stats);

// A colour image of the observed depth (near bright, far dark, black where missing): what the
// report shows when a dataset has no colour frame.
ColourImage DepthAsColour(const DepthImage& depth);

}  // namespace mcpose::report

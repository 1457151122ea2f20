// Synthetic RGB-D frames for unit tests: a mesh rendered by the reference rasterizer at a pose,
// its colour given by a function of the model point each pixel shows, over a background of
// random depths and colours.
#pragma once

#include <cmath>
#include <functional>

#include "core/rng.h"
#include "mcpose/camera.h"
#include "mcpose/image.h"
#include "mcpose/mesh.h"
#include "mcpose/se3.h"
#include "render/raster.h"

namespace mcpose::testing {

struct SyntheticFrame {
  Intrinsics K{600, 600, 160, 120, 320, 240};
  DepthImage depth;
  ColourImage colour;
  MaskImage visible;  // the object's pixels
};

// `colour_of` gives the RGBA of model point p (alpha 255).
inline SyntheticFrame RenderFrame(const Mesh& mesh, const SE3& T, const std::function<Rgba8(const Eigen::Vector3f&)>& colour_of,
                                  uint64_t seed) {
  SyntheticFrame f;
  const int w = f.K.width, h = f.K.height;
  render::RasterParams p;
  p.fx = static_cast<float>(f.K.fx), p.fy = static_cast<float>(f.K.fy);
  p.cx = static_cast<float>(f.K.cx), p.cy = static_cast<float>(f.K.cy);
  p.box = render::PixelRect{0, 0, w, h};
  std::vector<render::ScreenVertex> sv(mesh.vertices_m.size());
  render::ProjectVertices(mesh.vertices_m, T.R.cast<float>(), T.t.cast<float>(), p, sv);
  f.depth.width = w, f.depth.height = h;
  f.depth.depth_m.assign(static_cast<size_t>(w) * h, INFINITY);
  render::RasterizeDepthReference(sv, mesh.triangles, p, f.depth.depth_m.data(), nullptr);
  f.colour.width = w, f.colour.height = h;
  f.colour.rgba.resize(4 * static_cast<size_t>(w) * h);
  f.visible.width = w, f.visible.height = h;
  f.visible.values.assign(static_cast<size_t>(w) * h, 0);
  Rng rng(seed, 17);
  const SE3 T_obj_cam = T.Inverse();
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = static_cast<size_t>(y) * w + x;
      float& z = f.depth.depth_m[i];
      Rgba8 c;
      if (std::isinf(z)) {
        // Background: random depths behind the object (a wall would let a face pressed onto it
        // score like the object) and random colours.
        z = static_cast<float>(rng.Uniform(0.9, 1.5));
        c = {static_cast<uint8_t>(rng.NextU64()), static_cast<uint8_t>(rng.NextU64()),
             static_cast<uint8_t>(rng.NextU64()), 255};
      } else {
        const Eigen::Vector3d cam((x - f.K.cx) / f.K.fx * z, (y - f.K.cy) / f.K.fy * z, z);
        c = colour_of((T_obj_cam * cam).cast<float>());
        f.visible.values[i] = 255;
      }
      f.colour.rgba[4 * i] = c.r, f.colour.rgba[4 * i + 1] = c.g, f.colour.rgba[4 * i + 2] = c.b;
      f.colour.rgba[4 * i + 3] = 255;
    }
  return f;
}

}  // namespace mcpose::testing

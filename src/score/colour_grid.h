// A model's surface colour on a model-space grid: what the colour term of the weight reads at
// the surface point each rendered pixel shows (score/colour.h). Baked once per model from its
// texture or its vertex colours: the surface is sampled densely, each sample's colour
// interpolated (bilinear in the texture, barycentric between vertex colours), the samples of a
// cell averaged, and empty cells next to filled ones filled from their neighbours (a rendered
// point of a simplified mesh can lie a fraction of a cell off the surface).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "mcpose/image.h"
#include "mcpose/mesh.h"
#include "mcpose/options.h"
#include "score/colour.h"

namespace mcpose::appearance {

// Bilinear sample of `texture` at texture coordinates (u, v), v = 0 at the bottom row (OBJ),
// pixel centres at (i + 0.5) / width; edges clamp. Colour is weighted by alpha, and alpha is the
// interpolated alpha. NaN coordinates give an unknown colour (alpha 0).
Rgba8 SampleTexture(const ColourImage& texture, const Eigen::Vector2f& uv);
// The colour of `mesh` at barycentric coordinates `b` (summing to 1) of triangle `t`: the
// texture sampled at the interpolated texture coordinates, or the vertex colours interpolated
// (alpha-weighted); unknown (alpha 0) for a mesh without appearance.
Rgba8 SurfaceColour(const Mesh& mesh, size_t t, const Eigen::Vector3f& b);

class ColourGrid {
 public:
  // Cells along the mesh's longest side; the cell size follows (about 1.5-4 mm on YCB-Video).
  static constexpr int kCellsLongestSide = 64;
  // The grid of `mesh`'s appearance, or null if it has none.
  static std::shared_ptr<const ColourGrid> Build(const Mesh& mesh);

  // The grid as the colour kernels read it: the colour, or its form in another space.
  score::ColourLookup lookup(AppearanceOptions::Space space = AppearanceOptions::Space::kRgb) const;
  // The colour of the cell holding model point p (alpha 0 outside the grid or unknown).
  Rgba8 At(const Eigen::Vector3f& p_model) const;
  float cell_m() const { return cell_m_; }
  // Share of the cells the surface passes through whose colour is known.
  double known_fraction() const { return known_fraction_; }

 private:
  std::vector<uint32_t> cells_, chroma_cells_, intensity_hue_cells_;
  int nx_ = 0, ny_ = 0, nz_ = 0;
  Eigen::Vector3f origin_ = Eigen::Vector3f::Zero();
  float cell_m_ = 0;
  double known_fraction_ = 0;
};

// Packing of Rgba8 into the grid's cells (red in the low byte).
inline uint32_t Pack(const Rgba8& c) {
  return uint32_t{c.r} | (uint32_t{c.g} << 8) | (uint32_t{c.b} << 16) | (uint32_t{c.a} << 24);
}
inline Rgba8 Unpack(uint32_t v) {
  return {static_cast<uint8_t>(v), static_cast<uint8_t>(v >> 8), static_cast<uint8_t>(v >> 16),
          static_cast<uint8_t>(v >> 24)};
}

// A fingerprint of a mesh's appearance (colours, texture coordinates and texture), for caches.
uint64_t AppearanceFingerprint(const MeshAppearance& appearance);

}  // namespace mcpose::appearance

// Triangle meshes in metres, counter-clockwise winding seen from outside.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mcpose/image.h"
#include "mcpose/status.h"

namespace mcpose {

// 8-bit sRGB colour with a known flag in alpha (0: never seen; 255: known).
struct Rgba8 {
  uint8_t r = 0, g = 0, b = 0, a = 0;
  bool operator==(const Rgba8&) const = default;
};

// The surface colour of a mesh: per-vertex colours (PLY `red green blue [alpha]`), or a texture
// with each triangle's corner texture coordinates (OBJ `vt` + the material's `map_Kd`), or none.
struct MeshAppearance {
  std::vector<Rgba8> vertex_colours;  // empty, or one per vertex
  // Empty, or one per triangle: (u, v) of its corners, v = 0 at the bottom row of the texture
  // (the OBJ convention); NaN for a face without texture coordinates. Kept without a texture
  // too (a mesh's texture layout, which appearance capture fills).
  std::vector<std::array<Eigen::Vector2f, 3>> triangle_uv;
  std::shared_ptr<const ColourImage> texture;  // with triangle_uv
  std::string source;                          // the file the colour came from

  bool has_vertex_colours() const { return !vertex_colours.empty(); }
  bool has_texture() const { return texture != nullptr && !triangle_uv.empty(); }
  bool empty() const { return !has_vertex_colours() && !has_texture(); }
};

struct Mesh {
  std::vector<Eigen::Vector3f> vertices_m;
  std::vector<std::array<uint32_t, 3>> triangles;
  MeshAppearance appearance;  // optional; geometry alone decides depth

  // Axis-aligned bounds of the vertices (metres). Undefined for an empty mesh.
  Eigen::Vector3f BoundsMin() const;
  Eigen::Vector3f BoundsMax() const;

  // Ok, or an error naming `source` if the mesh is empty, has an index out of range, a
  // non-finite vertex, or no triangle of non-zero area (degenerate), or appearance arrays of
  // the wrong size. Zero-area triangles among valid ones are allowed (040_large_marker has 162).
  Status Validate(const std::string& source) const;
};

}  // namespace mcpose

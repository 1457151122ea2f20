// Wavefront OBJ meshes through tinyobjloader: positions, triangles and, where the file has them,
// texture coordinates with the material's diffuse texture (`map_Kd`, PNG or JPEG) as the
// mesh's appearance. A missing .mtl file means no colour (YCB-Video ships most models without
// theirs); a material naming a texture that does not exist means no colour too, with one
// warning per file; a texture that exists but cannot be decoded (truncated, not an image) is an
// error naming it. Normals and vertex colours are not read (YCB-Video's `v x y z r g b` lines
// carry one grey for every vertex).
#pragma once

#include <string>

#include "mcpose/mesh.h"
#include "mcpose/status.h"

namespace mcpose::io {

// Reads `path` and returns its mesh in metres, validated (Mesh::Validate). Vertices are the `v`
// lines in file order (never duplicated per v/vt/vn combination); triangles are the `f` lines in
// file order. Faces with more than three corners are an error. If `file_units_per_metre` is not
// 1, coordinates are divided by it in double before rounding to float.
StatusOr<Mesh> ReadObjMesh(const std::string& path, double file_units_per_metre = 1.0);

// Textures are reduced to at most this many pixels a side when read (box filter; the colour
// the engine compares is sampled on a grid of millimetres, coarser than a 4096-pixel scan).
inline constexpr int kMaxTextureSide = 1024;
// `image` halved (2 x 2 box filter, alpha-weighted colour) until no side exceeds max_side.
ColourImage ReduceTexture(ColourImage image, int max_side);

}  // namespace mcpose::io

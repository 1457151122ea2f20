// Wavefront OBJ meshes through tinyobjloader: positions and triangles only (normals, texture
// coordinates and materials are ignored; a missing .mtl file is not an error).
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

}  // namespace mcpose::io

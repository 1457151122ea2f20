// A small PLY mesh reader: ascii and binary_little_endian, vertex x/y/z (float or double; other
// vertex properties are skipped), faces as `property list <uchar|int|...> <int|uint|...>
// vertex_indices`. Only triangles are accepted. Other elements are skipped.
#pragma once

#include <string>

#include "mcpose/mesh.h"
#include "mcpose/status.h"

namespace mcpose::io {

// Reads `path` and returns its mesh in metres, validated (Mesh::Validate): every coordinate is
// parsed as double, divided by `file_units_per_metre` in double (1000 for BOP models in mm), then
// rounded to float. Vertex and triangle order are those of the file.
StatusOr<Mesh> ReadPlyMesh(const std::string& path, double file_units_per_metre = 1.0);

}  // namespace mcpose::io

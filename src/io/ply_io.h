// A small PLY mesh reader and writer: ascii and binary_little_endian, vertex x/y/z (float or
// double) and optional colours `red green blue [alpha]` (the BOP convention; uchar 0-255 or float
// 0-1; alpha 0 marks a colour never seen), other vertex properties skipped; faces as
// `property list <uchar|int|...> <int|uint|...> vertex_indices`. Only triangles are accepted.
// Other elements are skipped.
#pragma once

#include <string>

#include "mcpose/mesh.h"
#include "mcpose/status.h"

namespace mcpose::io {

// Reads `path` and returns its mesh in metres, validated (Mesh::Validate): every coordinate is
// parsed as double, divided by `file_units_per_metre` in double (1000 for BOP models in mm), then
// rounded to float. Vertex and triangle order are those of the file.
StatusOr<Mesh> ReadPlyMesh(const std::string& path, double file_units_per_metre = 1.0);

// Writes `mesh` as binary little-endian PLY: x y z doubles in file units (metres times
// `file_units_per_metre`: ReadPlyMesh gives the same vertices back), uchar red green blue alpha
// when it has vertex colours, and the triangles; atomically (temporary file and rename).
Status WritePlyMesh(const std::string& path, const Mesh& mesh, double file_units_per_metre = 1.0);

}  // namespace mcpose::io

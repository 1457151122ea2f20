#include "io/obj_io.h"

#include <tiny_obj_loader.h>

#include <cmath>
#include <exception>
#include <sstream>

#include "io/io_util.h"

namespace mcpose::io {
namespace {

// Materials are never used: answer every mtllib request with "no materials" instead of opening
// files (YCB-Video ships its OBJ files without the .mtl they name).
class NoMaterials : public tinyobj::MaterialReader {
 public:
  bool operator()(const std::string&, std::vector<tinyobj::material_t>*,
                  std::map<std::string, int>*, std::string*, std::string*) override {
    return true;
  }
};

StatusOr<Mesh> ParseObj(const std::string& path, const std::string& text,
                        double file_units_per_metre) {
  // Parse with tinyobjloader, keeping polygons as they are (no triangulation).
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warnings, errors;
  std::istringstream stream(text);
  NoMaterials no_materials;
  const bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warnings, &errors, &stream,
                                   &no_materials, /*triangulate=*/false,
                                   /*default_vcols_fallback=*/false);
  if (!ok) {
    return DataLoss(path + ": cannot parse OBJ file (tinyobjloader: " +
                    std::string(Trim(errors.empty() ? warnings : errors)) + ")");
  }
  if (attrib.vertices.size() % 3 != 0) {
    return DataLoss(path + ": OBJ positions are not 3-vectors");
  }

  // Positions in file order.
  Mesh mesh;
  const size_t num_vertices = attrib.vertices.size() / 3;
  mesh.vertices_m.reserve(num_vertices);
  for (size_t i = 0; i < num_vertices; ++i) {
    const tinyobj::real_t* v = &attrib.vertices[3 * i];
    if (file_units_per_metre == 1.0) {
      mesh.vertices_m.emplace_back(static_cast<float>(v[0]), static_cast<float>(v[1]),
                                   static_cast<float>(v[2]));
    } else {
      mesh.vertices_m.emplace_back(static_cast<float>(v[0] / file_units_per_metre),
                                   static_cast<float>(v[1] / file_units_per_metre),
                                   static_cast<float>(v[2] / file_units_per_metre));
    }
  }

  // Triangles of all shapes, in file order, by position index.
  size_t face_number = 0;
  for (const tinyobj::shape_t& shape : shapes) {
    const tinyobj::mesh_t& m = shape.mesh;
    size_t offset = 0;
    for (size_t f = 0; f < m.num_face_vertices.size(); ++f, ++face_number) {
      const size_t corners = m.num_face_vertices[f];
      if (corners != 3) {
        return InvalidArgument(path + ": face " + std::to_string(face_number) + " has " +
                               std::to_string(corners) +
                               " vertices; only triangle meshes are supported");
      }
      std::array<uint32_t, 3> triangle;
      for (size_t k = 0; k < 3; ++k) {
        const int index = m.indices[offset + k].vertex_index;
        if (index < 0 || static_cast<size_t>(index) >= num_vertices) {
          return InvalidArgument(path + ": face " + std::to_string(face_number) +
                                 " refers to vertex " + std::to_string(index + 1) + " of " +
                                 std::to_string(num_vertices));
        }
        triangle[k] = static_cast<uint32_t>(index);
      }
      mesh.triangles.push_back(triangle);
      offset += corners;
    }
  }
  MCPOSE_RETURN_IF_ERROR(mesh.Validate(path));
  return mesh;
}

}  // namespace

StatusOr<Mesh> ReadObjMesh(const std::string& path, double file_units_per_metre) {
  if (!std::isfinite(file_units_per_metre) || file_units_per_metre <= 0) {
    return InvalidArgument(path + ": units per metre must be finite and positive");
  }
  MCPOSE_ASSIGN_OR_RETURN(std::string text, ReadFileToString(path));
  try {
    return ParseObj(path, text, file_units_per_metre);
  } catch (const std::exception& e) {
    return Internal(path + ": OBJ read failed (" + e.what() + ")");
  }
}

}  // namespace mcpose::io

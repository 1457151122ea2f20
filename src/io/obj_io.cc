#include "io/obj_io.h"

#include <tiny_obj_loader.h>

#include <cmath>
#include <exception>
#include <filesystem>
#include <limits>
#include <mutex>
#include <set>
#include <string_view>
#include <cctype>
#include <sstream>

#include <spdlog/spdlog.h>

#include "mcpose/limits.h"
#include "mcpose/io_util.h"
#include "io/jpeg_io.h"

namespace mcpose::io {
namespace {

// Reads the .mtl files an OBJ names from its folder; a missing one gives no materials, not an
// error (YCB-Video ships most of its OBJ files without the .mtl they name).
class MaterialsBesideObj : public tinyobj::MaterialReader {
 public:
  explicit MaterialsBesideObj(std::string dir) : dir_(std::move(dir)) {}
  bool operator()(const std::string& name, std::vector<tinyobj::material_t>* materials,
                  std::map<std::string, int>* ids, std::string* warn, std::string* err) override {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(dir_ + "/" + name, ec)) return true;
    tinyobj::MaterialFileReader reader(dir_ + "/");
    return reader(name, materials, ids, warn, err);
  }

 private:
  std::string dir_;
};

// "nan", "inf", "infinity" in any case, with an optional sign: what printf and Python write for
// values that are not finite.
bool IsNonFiniteSpelling(std::string_view token) {
  if (!token.empty() && (token[0] == '+' || token[0] == '-')) token.remove_prefix(1);
  std::string lower(token);
  for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return lower == "nan" || lower == "inf" || lower == "infinity" || lower.starts_with("nan(");
}

// One warning per file and problem, however often the model is read.
void WarnOnce(const std::string& message) {
  static std::mutex mutex;
  static std::set<std::string> said;
  std::lock_guard<std::mutex> lock(mutex);
  if (said.insert(message).second) spdlog::warn("{}", message);
}

// tinyobjloader reads what it can and drops the rest (a vertex line of two numbers gets z = 0,
// letters read as 0, an unknown statement is skipped, an index beyond int overflows), so the
// text is checked line by line first: known statements only, each with the right count of
// numbers, face corners of 1-based (or negative, relative) indices that fit in an int.
// A normal that is not a number (`vn nan nan nan`, as some published scans have) is harmless:
// mcpose renders depth and colour without normals. Such normals are counted into
// *bad_normals, not refused.
Status CheckObjText(const std::string& path, std::string_view text, int* bad_normals) {
  *bad_normals = 0;
  const std::vector<std::string_view> lines = SplitLines(text);
  for (size_t i = 0; i < lines.size(); ++i) {
    const std::string_view line = Trim(lines[i]);
    if (line.empty() || line[0] == '#') continue;
    const std::vector<std::string_view> tokens = SplitWhitespace(line);
    const std::string_view keyword = tokens[0];
    const size_t n = tokens.size() - 1;
    const auto bad = [&](const std::string& what) {
      return DataLoss(path + ": line " + std::to_string(i + 1) + ": " + what + ", got '" +
                      std::string(line.substr(0, 80)) + "'");
    };
    const auto all_numbers = [&] {
      for (size_t k = 1; k < tokens.size(); ++k) {
        double v = 0;
        if (!ParseDouble(tokens[k], &v) || !std::isfinite(v)) return false;
      }
      return true;
    };
    if (keyword == "v") {
      // x y z, optionally w or a vertex colour r g b.
      if ((n != 3 && n != 4 && n != 6) || !all_numbers()) return bad("expected 'v x y z' (finite numbers)");
    } else if (keyword == "vt") {
      if (n < 1 || n > 3 || !all_numbers()) return bad("expected 'vt u [v [w]]' (finite numbers)");
    } else if (keyword == "vn") {
      if (n != 3) return bad("expected 'vn x y z' (finite numbers)");
      if (!all_numbers()) {
        // NaN or infinite, spelled as C and Python print them: harmless. Anything else is not a number.
        for (size_t k = 1; k < tokens.size(); ++k) {
          double v = 0;
          if (!ParseDouble(tokens[k], &v) && !IsNonFiniteSpelling(tokens[k]))
            return bad("expected 'vn x y z' (finite numbers)");
        }
        ++*bad_normals;
      }
    } else if (keyword == "f" || keyword == "l" || keyword == "p") {
      if (n < 1) return bad("expected vertex indices");
      // A face of one or two corners (a file cut in the middle of a line) is no triangle.
      if (keyword == "f" && n < 3) return bad("a face needs 3 corners, this one has " + std::to_string(n));
      for (size_t k = 1; k < tokens.size(); ++k) {
        // v, v/t, v//n or v/t/n; each index a nonzero int, the texture one may be empty in v//n.
        const std::vector<std::string_view> parts = Split(tokens[k], '/');
        if (parts.size() > 3) return bad("bad face corner '" + std::string(tokens[k]) + "'");
        for (size_t j = 0; j < parts.size(); ++j) {
          if (j == 1 && parts[j].empty() && parts.size() == 3) continue;
          int index = 0;
          if (!ParseInt(parts[j], &index) || index == 0 || index == std::numeric_limits<int>::min())
            return bad("face corner '" + std::string(tokens[k]) + "' is not a nonzero index that fits an int");
        }
      }
    } else if (keyword == "o" || keyword == "g" || keyword == "s" || keyword == "usemtl" || keyword == "mtllib" ||
               keyword == "vp") {
      continue;
    } else {
      return bad("unknown OBJ statement '" + std::string(keyword.substr(0, 16)) + "'");
    }
  }
  return Status::Ok();
}

StatusOr<Mesh> ParseObj(const std::string& path, const std::string& text,
                        double file_units_per_metre) {
  int bad_normals = 0;
  MCPOSE_RETURN_IF_ERROR(CheckObjText(path, text, &bad_normals));
  // Parse with tinyobjloader, keeping polygons as they are (no triangulation).
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warnings, errors;
  std::istringstream stream(text);
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  MaterialsBesideObj material_reader(dir.empty() ? "." : dir.string());
  const bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warnings, &errors, &stream,
                                   &material_reader, /*triangulate=*/false,
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

  // The texture: the first material's diffuse map. Faces of other materials get no colour.
  int textured_material = -1;
  for (size_t m = 0; m < materials.size() && textured_material < 0; ++m)
    if (!materials[m].diffuse_texname.empty()) textured_material = static_cast<int>(m);
  std::shared_ptr<const ColourImage> texture;
  if (textured_material >= 0) {
    const std::string texture_path = (dir / materials[textured_material].diffuse_texname).string();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(texture_path, ec)) {
      WarnOnce(path + ": no colour: its material names the texture " + texture_path + ", which does not exist");
    } else {
      // A texture that is there but cannot be decoded is bad input, not a model without colour.
      MCPOSE_ASSIGN_OR_RETURN(ColourImage image, ReadColourImage(texture_path));
      texture = std::make_shared<const ColourImage>(ReduceTexture(std::move(image), kMaxTextureSide));
    }
  }
  const size_t num_texcoords = attrib.texcoords.size() / 2;

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
      std::array<Eigen::Vector2f, 3> uv;
      // Texture coordinates of the textured material's faces, or of every face when there is
      // no texture (appearance capture bakes into them).
      const bool textured = texture ? m.material_ids[f] == textured_material : num_texcoords > 0;
      for (size_t k = 0; k < 3; ++k) {
        const int t = m.indices[offset + k].texcoord_index;
        uv[k] = textured && t >= 0 && static_cast<size_t>(t) < num_texcoords
                    ? Eigen::Vector2f(attrib.texcoords[2 * t], attrib.texcoords[2 * t + 1])
                    : Eigen::Vector2f::Constant(NAN);
        const int index = m.indices[offset + k].vertex_index;
        if (index < 0 || static_cast<size_t>(index) >= num_vertices) {
          return InvalidArgument(path + ": face " + std::to_string(face_number) +
                                 " refers to vertex " + std::to_string(index + 1) + " of " +
                                 std::to_string(num_vertices));
        }
        triangle[k] = static_cast<uint32_t>(index);
      }
      mesh.triangles.push_back(triangle);
      if (texture || num_texcoords > 0) mesh.appearance.triangle_uv.push_back(uv);
      offset += corners;
    }
  }
  if (texture) {
    mesh.appearance.texture = std::move(texture);
    mesh.appearance.source = path;
  }
  MCPOSE_RETURN_IF_ERROR(mesh.Validate(path));
  MCPOSE_RETURN_IF_ERROR(CheckMeshCoordinates(path, mesh));
  if (bad_normals > 0) {
    WarnOnce(path + ": " + std::to_string(bad_normals) + (bad_normals == 1 ? " normal is" : " normals are") +
             " not a number (vn nan); normals are not used, read anyway");
  }
  return mesh;
}

}  // namespace

ColourImage ReduceTexture(ColourImage image, int max_side) {
  while (image.width > max_side || image.height > max_side) {
    const int w = std::max(1, image.width / 2), h = std::max(1, image.height / 2);
    ColourImage half;
    half.width = w, half.height = h;
    half.rgba.resize(4 * static_cast<size_t>(w) * h);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        // The 2 x 2 block (one pixel wide where a side was odd and 1), colour weighted by alpha.
        int sum[4] = {0, 0, 0, 0}, count = 0;
        for (int dy = 0; dy < 2; ++dy)
          for (int dx = 0; dx < 2; ++dx) {
            const int sx = std::min(2 * x + dx, image.width - 1), sy = std::min(2 * y + dy, image.height - 1);
            const uint8_t* p = image.at(sx, sy);
            for (int c = 0; c < 3; ++c) sum[c] += p[c] * p[3];
            sum[3] += p[3];
            ++count;
          }
        uint8_t* q = half.rgba.data() + 4 * (static_cast<size_t>(y) * w + x);
        for (int c = 0; c < 3; ++c) q[c] = static_cast<uint8_t>(sum[3] > 0 ? (sum[c] + sum[3] / 2) / sum[3] : 0);
        q[3] = static_cast<uint8_t>((sum[3] + count / 2) / count);
      }
    }
    image = std::move(half);
  }
  return image;
}

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

#include "io/ply_io.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <limits>
#include <string_view>
#include <vector>

#include "mcpose/limits.h"
#include "mcpose/io_util.h"

namespace mcpose::io {
namespace {

enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

bool ParsePlyType(std::string_view name, PlyType* type) {
  static const struct {
    const char* name;
    PlyType type;
  } kTypes[] = {{"char", PlyType::kInt8},     {"int8", PlyType::kInt8},
                {"uchar", PlyType::kUint8},   {"uint8", PlyType::kUint8},
                {"short", PlyType::kInt16},   {"int16", PlyType::kInt16},
                {"ushort", PlyType::kUint16}, {"uint16", PlyType::kUint16},
                {"int", PlyType::kInt32},     {"int32", PlyType::kInt32},
                {"uint", PlyType::kUint32},   {"uint32", PlyType::kUint32},
                {"float", PlyType::kFloat32}, {"float32", PlyType::kFloat32},
                {"double", PlyType::kFloat64}, {"float64", PlyType::kFloat64}};
  for (const auto& t : kTypes) {
    if (name == t.name) {
      *type = t.type;
      return true;
    }
  }
  return false;
}

size_t TypeSize(PlyType type) {
  switch (type) {
    case PlyType::kInt8:
    case PlyType::kUint8: return 1;
    case PlyType::kInt16:
    case PlyType::kUint16: return 2;
    case PlyType::kInt32:
    case PlyType::kUint32:
    case PlyType::kFloat32: return 4;
    case PlyType::kFloat64: return 8;
  }
  return 0;
}

bool IsIntegerType(PlyType type) { return type != PlyType::kFloat32 && type != PlyType::kFloat64; }

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kFloat32;
  bool is_list = false;
  PlyType count_type = PlyType::kUint8;  // lists only
};

struct PlyElement {
  std::string name;
  size_t count = 0;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  bool binary = false;
  std::vector<PlyElement> elements;
  size_t body_offset = 0;  // first byte after "end_header\n"
};

Status ParseHeader(const std::string& path, const std::string& bytes, PlyHeader* header) {
  const std::string_view text(bytes);
  size_t pos = 0;
  int line_number = 0;
  bool saw_format = false;
  auto error = [&](const std::string& what) {
    return DataLoss(path + ": PLY header line " + std::to_string(line_number) + ": " + what);
  };
  while (true) {
    const size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) {
      return DataLoss(path + ": PLY header has no end_header line (truncated or not a PLY file)");
    }
    const std::string_view line = Trim(text.substr(pos, end - pos));
    pos = end + 1;
    ++line_number;
    const std::vector<std::string_view> tokens = SplitWhitespace(line);
    if (line_number == 1) {
      if (line != "ply") return DataLoss(path + ": not a PLY file (first line is not 'ply')");
      continue;
    }
    if (tokens.empty() || tokens[0] == "comment" || tokens[0] == "obj_info") continue;
    if (tokens[0] == "format") {
      if (tokens.size() < 2) return error("incomplete format line");
      if (tokens[1] == "ascii") {
        header->binary = false;
      } else if (tokens[1] == "binary_little_endian") {
        header->binary = true;
      } else {
        return InvalidArgument(path + ": unsupported PLY format '" + std::string(tokens[1]) +
                               "' (ascii and binary_little_endian are supported)");
      }
      saw_format = true;
    } else if (tokens[0] == "element") {
      int count = -1;
      if (tokens.size() != 3 || !ParseInt(tokens[2], &count) || count < 0) {
        return error("expected 'element <name> <count>', got '" + std::string(line) + "'");
      }
      header->elements.push_back({std::string(tokens[1]), static_cast<size_t>(count), {}});
    } else if (tokens[0] == "property") {
      if (header->elements.empty()) return error("property before any element");
      PlyProperty property;
      if (tokens.size() == 5 && tokens[1] == "list") {
        property.is_list = true;
        if (!ParsePlyType(tokens[2], &property.count_type) || !IsIntegerType(property.count_type) ||
            !ParsePlyType(tokens[3], &property.type)) {
          return error("bad list property '" + std::string(line) + "'");
        }
        property.name = std::string(tokens[4]);
      } else if (tokens.size() == 3) {
        if (!ParsePlyType(tokens[1], &property.type)) {
          return error("unknown property type '" + std::string(tokens[1]) + "'");
        }
        property.name = std::string(tokens[2]);
      } else {
        return error("bad property line '" + std::string(line) + "'");
      }
      header->elements.back().properties.push_back(property);
    } else if (tokens[0] == "end_header") {
      break;
    } else {
      return error("unknown keyword '" + std::string(tokens[0]) + "'");
    }
  }
  if (!saw_format) return DataLoss(path + ": PLY header has no format line");
  header->body_offset = pos;
  // Each item takes at least a byte of the body (binary: its scalars and list counts; ascii: a
  // character): the counts must fit what follows the header, and an element with items but no
  // properties has nothing to read.
  const size_t body = bytes.size() - pos;
  size_t least = 0;
  for (const PlyElement& e : header->elements) {
    if (e.count > 0 && e.properties.empty())
      return DataLoss(path + ": PLY element '" + e.name + "' has " + std::to_string(e.count) + " items but no properties");
    size_t item = 0;
    for (const PlyProperty& p : e.properties) item += TypeSize(p.is_list ? p.count_type : p.type);
    least += e.count * (header->binary ? item : 1);
    if (least > body)
      return DataLoss(path + ": truncated or forged: the PLY header declares more items than the file's " +
                      std::to_string(body) + " bytes of data can hold (element '" + e.name + "', " +
                      std::to_string(e.count) + " items)");
  }
  return Status::Ok();
}

// Sequential reader of property values from the body, ascii or binary.
class BodyReader {
 public:
  BodyReader(const std::string& path, const std::string& bytes, size_t offset, bool binary)
      : path_(path), bytes_(bytes), pos_(offset), binary_(binary) {}

  // Starts an element record (ascii: the next non-empty line).
  Status BeginRecord(const std::string& element, size_t index) {
    element_ = &element;
    index_ = index;
    if (binary_) return Status::Ok();
    const std::string_view text(bytes_);
    while (true) {
      if (pos_ >= text.size()) return Truncated();
      size_t end = text.find('\n', pos_);
      if (end == std::string_view::npos) end = text.size();
      const std::string_view line = text.substr(pos_, end - pos_);
      pos_ = end + 1;
      tokens_ = SplitWhitespace(line);
      next_token_ = 0;
      if (!tokens_.empty()) return Status::Ok();
    }
  }

  Status Read(PlyType type, double* value) {
    if (binary_) {
      const size_t size = TypeSize(type);
      if (pos_ + size > bytes_.size()) return Truncated();
      const char* p = bytes_.data() + pos_;
      pos_ += size;
      *value = DecodeLittleEndian(type, p);
      return Status::Ok();
    }
    if (next_token_ >= tokens_.size()) {
      return DataLoss(Where() + "too few values on the line");
    }
    const std::string_view token = tokens_[next_token_++];
    if (!ParseDouble(token, value)) {
      return DataLoss(Where() + "'" + std::string(token) + "' is not a number");
    }
    return Status::Ok();
  }

  size_t position() const { return pos_; }
  std::string Where() const {
    return path_ + ": " + *element_ + " " + std::to_string(index_) + ": ";
  }

 private:
  static double DecodeLittleEndian(PlyType type, const char* p) {
    // The supported machines are little-endian, as is the file: a plain copy decodes.
    switch (type) {
      case PlyType::kInt8: return static_cast<double>(static_cast<int8_t>(*p));
      case PlyType::kUint8: return static_cast<double>(static_cast<uint8_t>(*p));
      case PlyType::kInt16: return Copy<int16_t>(p);
      case PlyType::kUint16: return Copy<uint16_t>(p);
      case PlyType::kInt32: return Copy<int32_t>(p);
      case PlyType::kUint32: return Copy<uint32_t>(p);
      case PlyType::kFloat32: return Copy<float>(p);
      case PlyType::kFloat64: return Copy<double>(p);
    }
    return 0;
  }
  template <typename T>
  static double Copy(const char* p) {
    T v;
    std::memcpy(&v, p, sizeof(T));
    return static_cast<double>(v);
  }
  Status Truncated() const {
    return DataLoss(path_ + ": PLY file is truncated (ends in " + *element_ + " " +
                    std::to_string(index_) + ")");
  }

  const std::string& path_;
  const std::string& bytes_;
  size_t pos_;
  bool binary_;
  const std::string* element_ = nullptr;
  size_t index_ = 0;
  std::vector<std::string_view> tokens_;
  size_t next_token_ = 0;
};

int FindProperty(const PlyElement& element, const char* name) {
  for (size_t i = 0; i < element.properties.size(); ++i) {
    if (element.properties[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

StatusOr<Mesh> ParsePly(const std::string& path, const std::string& bytes,
                        double file_units_per_metre) {
  PlyHeader header;
  MCPOSE_RETURN_IF_ERROR(ParseHeader(path, bytes, &header));

  // Check the elements we need before reading anything.
  const PlyElement* vertex_element = nullptr;
  const PlyElement* face_element = nullptr;
  for (const PlyElement& e : header.elements) {
    if (e.name == "vertex") vertex_element = &e;
    if (e.name == "face") face_element = &e;
  }
  if (!vertex_element) return InvalidArgument(path + ": PLY file has no vertex element");
  int xyz[3] = {FindProperty(*vertex_element, "x"), FindProperty(*vertex_element, "y"),
                FindProperty(*vertex_element, "z")};
  for (int i = 0; i < 3; ++i) {
    if (xyz[i] < 0 || vertex_element->properties[xyz[i]].is_list) {
      return InvalidArgument(path + ": PLY vertex element has no scalar property '" +
                             std::string(1, "xyz"[i]) + "'");
    }
  }
  // Vertex colours: red, green, blue and optionally alpha; integer types hold 0-255, float
  // types 0-1 (alpha 0 marks a colour never seen).
  int rgba[4] = {FindProperty(*vertex_element, "red"), FindProperty(*vertex_element, "green"),
                 FindProperty(*vertex_element, "blue"), FindProperty(*vertex_element, "alpha")};
  const bool has_colour = rgba[0] >= 0 && rgba[1] >= 0 && rgba[2] >= 0;
  for (int c = 0; c < 4 && has_colour; ++c) {
    if (rgba[c] >= 0 && vertex_element->properties[rgba[c]].is_list)
      return InvalidArgument(path + ": PLY vertex colour property '" + vertex_element->properties[rgba[c]].name +
                             "' is a list");
  }
  int indices_property = -1;
  if (face_element) {
    indices_property = FindProperty(*face_element, "vertex_indices");
    if (indices_property < 0) indices_property = FindProperty(*face_element, "vertex_index");
    if (indices_property < 0 || !face_element->properties[indices_property].is_list ||
        !IsIntegerType(face_element->properties[indices_property].type)) {
      return InvalidArgument(path + ": PLY face element has no integer list 'vertex_indices'");
    }
  }

  // Guard the reservations against absurd counts in a damaged header.
  const size_t body_bytes = bytes.size() - header.body_offset;
  Mesh mesh;
  mesh.vertices_m.reserve(std::min(vertex_element->count, body_bytes / 3));
  if (face_element) mesh.triangles.reserve(std::min(face_element->count, body_bytes / 4));

  BodyReader reader(path, bytes, header.body_offset, header.binary);
  for (const PlyElement& element : header.elements) {
    const bool is_vertex = &element == vertex_element;
    const bool is_face = &element == face_element;
    for (size_t n = 0; n < element.count; ++n) {
      MCPOSE_RETURN_IF_ERROR(reader.BeginRecord(element.name, n));
      double position[3] = {0, 0, 0};
      double colour[4] = {0, 0, 0, -1};
      std::array<uint32_t, 3> triangle = {0, 0, 0};
      for (size_t p = 0; p < element.properties.size(); ++p) {
        const PlyProperty& property = element.properties[p];
        if (!property.is_list) {
          double value = 0;
          MCPOSE_RETURN_IF_ERROR(reader.Read(property.type, &value));
          if (is_vertex) {
            for (int i = 0; i < 3; ++i) {
              if (static_cast<int>(p) == xyz[i]) position[i] = value;
            }
            for (int c = 0; c < 4 && has_colour; ++c) {
              if (static_cast<int>(p) != rgba[c]) continue;
              const double scale = IsIntegerType(property.type) ? 1.0 : 255.0;
              const double v = value * scale;
              if (!(v >= 0 && v <= 255.5))
                return InvalidArgument(reader.Where() + "colour '" + property.name + "' " + std::to_string(value) +
                                       " is outside " + (scale == 1.0 ? "0-255" : "0-1"));
              colour[c] = v;
            }
          }
          continue;
        }
        // List property: count, then the items.
        double count_value = 0;
        MCPOSE_RETURN_IF_ERROR(reader.Read(property.count_type, &count_value));
        // A list cannot hold more items than the file has bytes.
        if (!(count_value >= 0 && count_value <= static_cast<double>(bytes.size())) ||
            count_value != std::floor(count_value)) {
          return DataLoss(reader.Where() + "bad list length " + limits::Num(count_value));
        }
        const size_t count = static_cast<size_t>(count_value);
        const bool is_indices = is_face && static_cast<int>(p) == indices_property;
        if (is_indices && count != 3) {
          return InvalidArgument(reader.Where() + "has " + std::to_string(count) +
                                 " vertices; only triangle meshes are supported");
        }
        for (size_t k = 0; k < count; ++k) {
          double value = 0;
          MCPOSE_RETURN_IF_ERROR(reader.Read(property.type, &value));
          if (!is_indices) continue;
          if (!(value >= 0 && value < static_cast<double>(vertex_element->count)) || value != std::floor(value)) {
            return InvalidArgument(reader.Where() + "vertex index " + limits::Num(value) + " is not an integer in [0, " +
                                   std::to_string(vertex_element->count) + ")");
          }
          triangle[k] = static_cast<uint32_t>(value);
        }
      }
      if (is_vertex) {
        for (int i = 0; i < 3; ++i) {
          if (!limits::CoordinateOk(position[i] / file_units_per_metre))
            return InvalidArgument(reader.Where() + std::string(1, "xyz"[i]) + " = " +
                                   limits::Num(position[i] / file_units_per_metre) +
                                   " m is not finite or not under " + limits::Num(limits::kMaxCoordinateM) + " m");
        }
        // Divide in double, round once to float: the same float as a metre-valued source.
        mesh.vertices_m.emplace_back(static_cast<float>(position[0] / file_units_per_metre),
                                     static_cast<float>(position[1] / file_units_per_metre),
                                     static_cast<float>(position[2] / file_units_per_metre));
        if (has_colour) {
          auto byte = [](double v) { return static_cast<uint8_t>(std::lround(std::min(v, 255.0))); };
          mesh.appearance.vertex_colours.push_back(
              {byte(colour[0]), byte(colour[1]), byte(colour[2]), colour[3] < 0 ? uint8_t{255} : byte(colour[3])});
        }
      }
      if (is_face) mesh.triangles.push_back(triangle);
    }
  }
  if (has_colour) mesh.appearance.source = path;
  MCPOSE_RETURN_IF_ERROR(mesh.Validate(path));
  MCPOSE_RETURN_IF_ERROR(CheckMeshCoordinates(path, mesh));
  return mesh;
}

}  // namespace

StatusOr<Mesh> ReadPlyMesh(const std::string& path, double file_units_per_metre) {
  if (!std::isfinite(file_units_per_metre) || file_units_per_metre <= 0) {
    return InvalidArgument(path + ": units per metre must be finite and positive");
  }
  MCPOSE_ASSIGN_OR_RETURN(std::string bytes, ReadFileToString(path));
  try {
    return ParsePly(path, bytes, file_units_per_metre);
  } catch (const std::exception& e) {
    return Internal(path + ": PLY read failed (" + e.what() + ")");
  }
}

Status WritePlyMesh(const std::string& path, const Mesh& mesh, double file_units_per_metre) {
  static_assert(std::endian::native == std::endian::little, "the writer stores the host's bytes");
  MCPOSE_RETURN_IF_ERROR(mesh.Validate(path));
  const bool colour = mesh.appearance.has_vertex_colours();
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment written by mcpose\nelement vertex " +
                    std::to_string(mesh.vertices_m.size()) + "\nproperty double x\nproperty double y\nproperty double z\n";
  if (colour) out += "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n";
  out += "element face " + std::to_string(mesh.triangles.size()) +
         "\nproperty list uchar int vertex_indices\nend_header\n";
  auto put = [&out](const void* p, size_t n) { out.append(static_cast<const char*>(p), n); };
  for (size_t i = 0; i < mesh.vertices_m.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      // In double: reading divides by the same factor and rounds to the same float.
      const double v = static_cast<double>(mesh.vertices_m[i][k]) * file_units_per_metre;
      put(&v, sizeof v);
    }
    if (colour) put(&mesh.appearance.vertex_colours[i], 4);
  }
  for (const auto& t : mesh.triangles) {
    const uint8_t three = 3;
    put(&three, 1);
    for (uint32_t v : t) {
      const int32_t index = static_cast<int32_t>(v);
      put(&index, sizeof index);
    }
  }
  return WriteFileAtomic(path, out);
}

}  // namespace mcpose::io

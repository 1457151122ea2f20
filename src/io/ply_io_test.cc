#include "io/ply_io.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "test_data.h"

namespace mcpose {
namespace {

std::string WriteText(const std::string& test, const std::string& text) {
  const std::string path = (testing::TempDir(test) / "mesh.ply").string();
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

void ExpectError(const StatusOr<Mesh>& mesh, const std::string& path, const std::string& what) {
  ASSERT_FALSE(mesh.ok());
  EXPECT_NE(mesh.status().message().find(path), std::string::npos) << mesh.status().message();
  EXPECT_NE(mesh.status().message().find(what), std::string::npos) << mesh.status().message();
}

constexpr const char* kAsciiTetra =
    "ply\n"
    "format ascii 1.0\n"
    "comment a tetrahedron in mm, with extra properties to skip\n"
    "element vertex 4\n"
    "property double x\n"
    "property float nx\n"
    "property float y\n"
    "property float z\n"
    "property uchar red\n"
    "element face 4\n"
    "property list uchar int vertex_indices\n"
    "property list uchar float texcoord\n"
    "element edge 1\n"
    "property int vertex1\n"
    "property int vertex2\n"
    "end_header\n"
    "0 1 0 0 255\n"
    "1000 0 0 0 255\n"
    "0 0 1000 0 255\n"
    "0 0 0 1000 255\n"
    "3 0 2 1 0\n"
    "3 0 1 3 2 0.5 0.5\n"
    "3 0 3 2 0\n"
    "3 1 2 3 1 0.25\n"
    "0 1\n";

TEST(PlyIoTest, AsciiWithSkippedProperties) {
  const std::string path = WriteText("ply_ascii", kAsciiTetra);
  StatusOr<Mesh> mesh = io::ReadPlyMesh(path, 1000.0);
  ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
  ASSERT_EQ(mesh->vertices_m.size(), 4u);
  EXPECT_EQ(mesh->vertices_m[1], Eigen::Vector3f(1, 0, 0));
  EXPECT_EQ(mesh->vertices_m[3], Eigen::Vector3f(0, 0, 1));
  ASSERT_EQ(mesh->triangles.size(), 4u);
  EXPECT_EQ(mesh->triangles[1], (std::array<uint32_t, 3>{0, 1, 3}));
  EXPECT_EQ(mesh->triangles[3], (std::array<uint32_t, 3>{1, 2, 3}));
}

// Binary little-endian: float xyz + double extra, face list uint count / uint indices.
std::string BinaryTetra(size_t cut_bytes = 0) {
  std::string text =
      "ply\n"
      "format binary_little_endian 1.0\n"
      "element vertex 4\n"
      "property float x\n"
      "property float y\n"
      "property float z\n"
      "property double quality\n"
      "element face 4\n"
      "property uchar flags\n"
      "property list int uint vertex_indices\n"
      "end_header\n";
  auto put = [&](const auto& value) {
    char bytes[sizeof(value)];
    std::memcpy(bytes, &value, sizeof(value));
    text.append(bytes, sizeof(value));
  };
  const float xyz[4][3] = {{0, 0, 0}, {0.1f, 0, 0}, {0, 0.1f, 0}, {0, 0, 0.1f}};
  for (const auto& v : xyz) {
    put(v[0]);
    put(v[1]);
    put(v[2]);
    put(3.5);
  }
  const uint32_t faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  for (const auto& f : faces) {
    put(uint8_t{7});
    put(int32_t{3});
    put(f[0]);
    put(f[1]);
    put(f[2]);
  }
  text.resize(text.size() - cut_bytes);
  return text;
}

TEST(PlyIoTest, BinaryLittleEndian) {
  const std::string path = WriteText("ply_binary", BinaryTetra());
  StatusOr<Mesh> mesh = io::ReadPlyMesh(path);
  ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
  ASSERT_EQ(mesh->vertices_m.size(), 4u);
  EXPECT_EQ(mesh->vertices_m[2], Eigen::Vector3f(0, 0.1f, 0));
  ASSERT_EQ(mesh->triangles.size(), 4u);
  EXPECT_EQ(mesh->triangles[0], (std::array<uint32_t, 3>{0, 2, 1}));
}

TEST(PlyIoTest, TruncatedBinary) {
  const std::string path = WriteText("ply_binary_cut", BinaryTetra(5));
  ExpectError(io::ReadPlyMesh(path), path, "truncated");
}

TEST(PlyIoTest, MissingFile) {
  const std::string path = "/nonexistent/mcpose/obj_000001.ply";
  StatusOr<Mesh> mesh = io::ReadPlyMesh(path);
  EXPECT_EQ(mesh.status().code(), StatusCode::kNotFound);
  ExpectError(mesh, path, "does not exist");
}

TEST(PlyIoTest, EmptyMesh) {
  const std::string path = WriteText("ply_empty",
                                     "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n"
                                     "property float y\nproperty float z\nelement face 0\n"
                                     "property list uchar int vertex_indices\nend_header\n");
  ExpectError(io::ReadPlyMesh(path), path, "mesh is empty");
}

TEST(PlyIoTest, DegenerateMesh) {
  // Three collinear points: both triangles have zero area.
  const std::string path = WriteText("ply_degenerate",
                                     "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                     "property float y\nproperty float z\nelement face 2\n"
                                     "property list uchar int vertex_indices\nend_header\n"
                                     "0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n3 2 1 0\n");
  ExpectError(io::ReadPlyMesh(path), path, "degenerate");
}

TEST(PlyIoTest, QuadsAreRefused) {
  const std::string path = WriteText("ply_quad",
                                     "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
                                     "property float y\nproperty float z\nelement face 1\n"
                                     "property list uchar int vertex_indices\nend_header\n"
                                     "0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n");
  ExpectError(io::ReadPlyMesh(path), path, "face 0: has 4 vertices");
}

TEST(PlyIoTest, BadInput) {
  std::string path = WriteText("ply_not_ply", "solid cube\nfacet normal 0 0 1\n");
  ExpectError(io::ReadPlyMesh(path), path, "not a PLY file");

  path = WriteText("ply_big_endian",
                   "ply\nformat binary_big_endian 1.0\nelement vertex 0\nend_header\n");
  ExpectError(io::ReadPlyMesh(path), path, "unsupported PLY format");

  path = WriteText("ply_bad_number",
                   "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                   "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                   "end_header\n0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n");
  ExpectError(io::ReadPlyMesh(path), path, "vertex 1: 'zero' is not a number");

  path = WriteText("ply_short",
                   "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                   "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                   "end_header\n0 0 0\n1 0 0\n");
  ExpectError(io::ReadPlyMesh(path), path, "truncated");

  path = WriteText("ply_index",
                   "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                   "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                   "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
  ExpectError(io::ReadPlyMesh(path), path, "vertex index 7 is not an integer in [0, 3)");

  // Counts the body cannot hold, or items with nothing to read, are refused at the header.
  path = WriteText("ply_huge_count", "ply\nformat binary_little_endian 1.0\nelement vertex 2147483647\n"
                                     "property float x\nproperty float y\nproperty float z\nend_header\n0123");
  ExpectError(io::ReadPlyMesh(path), path, "declares more items than the file's 4 bytes");
  path = WriteText("ply_no_properties", "ply\nformat binary_little_endian 1.0\nelement junk 2147483647\n"
                                        "element vertex 0\nproperty float x\nend_header\n");
  ExpectError(io::ReadPlyMesh(path), path, "element 'junk' has 2147483647 items but no properties");

  path = WriteText("ply_no_header_end", "ply\nformat ascii 1.0\nelement vertex 3\n");
  ExpectError(io::ReadPlyMesh(path), path, "end_header");
}

TEST(PlyIoTest, RealBopModel) {
  const std::string path = testing::BopDir() + "/models/obj_000003.ply";
  StatusOr<Mesh> mesh = io::ReadPlyMesh(path, 1000.0);
  ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
  EXPECT_EQ(mesh->vertices_m.size(), 7866u);
  EXPECT_EQ(mesh->triangles.size(), 15728u);
  // models_info.json: min_x -23.929 mm, size_x 49.544 mm.
  EXPECT_NEAR(mesh->BoundsMin().x(), -0.023929, 1e-6);
  EXPECT_NEAR(mesh->BoundsMax().x() - mesh->BoundsMin().x(), 0.049544, 1e-6);
}

}  // namespace
}  // namespace mcpose

#include "io/obj_io.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include "io/ply_io.h"
#include "io/ycbv_names.h"
#include "test_data.h"

namespace mcpose {
namespace {

std::string WriteText(const std::string& test, const std::string& text) {
  const std::string path = (testing::TempDir(test) / "mesh.obj").string();
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

TEST(ObjIoTest, PositionsInFileOrderNotDuplicatedPerCorner) {
  // Separate v/vt/vn indices, a missing material file, vertex colours and a group.
  const std::string path = WriteText("obj_small",
                                     "mtllib ./missing.mtl\n"
                                     "v 0 0 0 0.5 0.5 0.5\n"
                                     "v 1 0 0 0.5 0.5 0.5\n"
                                     "v 0 1 0 0.5 0.5 0.5\n"
                                     "v 0 0 1 0.5 0.5 0.5\n"
                                     "vt 0 0\nvt 1 0\nvt 0 1\n"
                                     "vn 0 0 1\nvn 1 0 0\n"
                                     "usemtl grey\n"
                                     "f 1/1/1 3/2/1 2/3/1\n"
                                     "g side\n"
                                     "f 1/3/2 2/1/2 4/2/2\n"
                                     "f 1//1 4//1 3//1\n"
                                     "f -3 -2 -1\n");
  StatusOr<Mesh> mesh = io::ReadObjMesh(path);
  ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
  ASSERT_EQ(mesh->vertices_m.size(), 4u);
  EXPECT_EQ(mesh->vertices_m[1], Eigen::Vector3f(1, 0, 0));
  ASSERT_EQ(mesh->triangles.size(), 4u);
  EXPECT_EQ(mesh->triangles[0], (std::array<uint32_t, 3>{0, 2, 1}));
  EXPECT_EQ(mesh->triangles[1], (std::array<uint32_t, 3>{0, 1, 3}));
  EXPECT_EQ(mesh->triangles[2], (std::array<uint32_t, 3>{0, 3, 2}));
  EXPECT_EQ(mesh->triangles[3], (std::array<uint32_t, 3>{1, 2, 3}));

  StatusOr<Mesh> mm = io::ReadObjMesh(path, 1000.0);
  ASSERT_TRUE(mm.ok());
  EXPECT_EQ(mm->vertices_m[1], Eigen::Vector3f(0.001f, 0, 0));
}

TEST(ObjIoTest, BadInput) {
  std::string path = WriteText("obj_quad", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
  StatusOr<Mesh> mesh = io::ReadObjMesh(path);
  ASSERT_FALSE(mesh.ok());
  EXPECT_NE(mesh.status().message().find(path + ": face 0 has 4 vertices"), std::string::npos)
      << mesh.status().message();

  path = WriteText("obj_empty", "# nothing\n");
  mesh = io::ReadObjMesh(path);
  ASSERT_FALSE(mesh.ok());
  EXPECT_NE(mesh.status().message().find(path + ": mesh is empty"), std::string::npos)
      << mesh.status().message();

  path = WriteText("obj_degenerate", "v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\n");
  mesh = io::ReadObjMesh(path);
  ASSERT_FALSE(mesh.ok());
  EXPECT_NE(mesh.status().message().find("degenerate"), std::string::npos);

  path = WriteText("obj_zero_index", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
  mesh = io::ReadObjMesh(path);
  ASSERT_FALSE(mesh.ok());
  EXPECT_NE(mesh.status().message().find(path), std::string::npos) << mesh.status().message();

  // A file cut in the middle of a face line: the face's missing corners are an error, not a
  // face dropped in silence.
  path = WriteText("obj_cut", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4");
  mesh = io::ReadObjMesh(path);
  ASSERT_FALSE(mesh.ok());
  EXPECT_NE(mesh.status().message().find(path + ": line 6: a face needs 3 corners, this one has 2"), std::string::npos)
      << mesh.status().message();

  path = "/nonexistent/mcpose/model.obj";
  mesh = io::ReadObjMesh(path);
  EXPECT_EQ(mesh.status().code(), StatusCode::kNotFound);
  EXPECT_NE(mesh.status().message().find(path), std::string::npos);
}

// What spdlog's default logger says while `f` runs.
template <typename F>
std::string Warnings(F&& f) {
  std::ostringstream out;
  auto sink = std::make_shared<spdlog::sinks::ostream_sink_mt>(out);
  auto previous = spdlog::default_logger();
  spdlog::set_default_logger(std::make_shared<spdlog::logger>("test", sink));
  f();
  spdlog::set_default_logger(previous);
  return out.str();
}

size_t Count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// Published scans carry normals that are not numbers (`vn nan nan nan`); normals are not used,
// so the mesh is read, with one warning naming the file and the count, however often it is read.
TEST(ObjIoTest, NormalsThatAreNotNumbersAreReadWithOneWarning) {
  const std::string path = WriteText("obj_nan_normals",
                                     "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                     "vn nan nan nan\nvn 0 0 1\nvn -NaN inf -inf\n"
                                     "f 1//1 2//2 3//3\n");
  std::string said = Warnings([&] {
    for (int k = 0; k < 3; ++k) {
      StatusOr<Mesh> mesh = io::ReadObjMesh(path);
      ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
      EXPECT_EQ(mesh->triangles.size(), 1u);
    }
  });
  EXPECT_EQ(Count(said, path + ": 2 normals are not a number"), 1u) << said;
  // Words that are not numbers stay errors, in normals as anywhere.
  const std::string bad = WriteText("obj_word_normal", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn x 0 1\nf 1 2 3\n");
  StatusOr<Mesh> mesh = io::ReadObjMesh(bad);
  ASSERT_FALSE(mesh.ok());
  EXPECT_NE(mesh.status().message().find(bad + ": line 4"), std::string::npos) << mesh.status().message();
}

// The three published scans of ycbv_textured that have such a normal load, each with its warning.
TEST(ObjIoTest, TexturedScansWithNanNormalsLoad) {
  const std::string models = testing::DataDir() + "/ycbv_textured/models";
  if (!std::filesystem::exists(models)) GTEST_SKIP() << "no " << models;
  for (const char* name : {"007_tuna_fish_can", "025_mug", "051_large_clamp"}) {
    const std::string path = models + "/" + name + "/textured_simple.obj";
    const std::string said = Warnings([&] {
      StatusOr<Mesh> mesh = io::ReadObjMesh(path);
      ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
      EXPECT_TRUE(mesh->appearance.has_texture()) << path;
    });
    EXPECT_EQ(Count(said, path + ": 1 normal is not a number"), 1u) << said;
  }
}

// The native OBJ (metres, 6 decimals) and the BOP PLY (mm, 4 decimals) of the same model hold the
// same numbers: both readers must give the same floats (up to a rare last-bit rounding) and the
// same triangles in the same order.
TEST(ObjPlyIoTest, NativeAndBopMeshesAgree) {
  double max_diff_m = 0;
  size_t differing_floats = 0, total_floats = 0;
  for (int obj_id = 1; obj_id <= 21; ++obj_id) {
    const std::string name = io::YcbvClassNames()[obj_id - 1];
    char ply_name[32];
    std::snprintf(ply_name, sizeof(ply_name), "obj_%06d.ply", obj_id);
    StatusOr<Mesh> obj = io::ReadObjMesh(testing::YcbvDir() + "/models/" + name +
                                         "/textured_simple.obj");
    StatusOr<Mesh> ply = io::ReadPlyMesh(testing::BopDir() + "/models/" + ply_name, 1000.0);
    ASSERT_TRUE(obj.ok()) << obj.status().ToString();
    ASSERT_TRUE(ply.ok()) << ply.status().ToString();
    EXPECT_EQ(obj->triangles.size(), 15728u) << name;
    ASSERT_EQ(obj->vertices_m.size(), ply->vertices_m.size()) << name;
    EXPECT_EQ(obj->triangles, ply->triangles) << name;
    for (size_t i = 0; i < obj->vertices_m.size(); ++i) {
      for (int k = 0; k < 3; ++k) {
        const float a = obj->vertices_m[i][k], b = ply->vertices_m[i][k];
        max_diff_m = std::max(max_diff_m, std::fabs(static_cast<double>(a) - b));
        differing_floats += (a != b);
        ++total_floats;
      }
    }
  }
  std::printf("[ObjPlyIoTest] 21 models: max |OBJ - PLY| = %.3g m, %zu of %zu floats differ\n",
              max_diff_m, differing_floats, total_floats);
  EXPECT_LT(max_diff_m, 1e-7);
}

}  // namespace
}  // namespace mcpose

// Colour input: PNG and JPEG colour images, OBJ textures, PLY vertex colours, colour frames of
// both dataset layouts; each bad input one clear error naming the file (a missing texture: a
// model without colour).
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "mcpose/io_util.h"
#include "io/jpeg_io.h"
#include "io/obj_io.h"
#include "io/ply_io.h"
#include "mcpose/png_io.h"
#include "mcpose/dataset.h"
#include "synthetic_mesh.h"
#include "test_data.h"

namespace mcpose {
namespace {

namespace fs = std::filesystem;

std::string Bytes(const std::string& path) { return std::move(io::ReadFileToString(path)).value(); }
void Write(const fs::path& p, const std::string& bytes) { std::ofstream(p, std::ios::binary) << bytes; }

TEST(ColourIo, RealFramesAndTexturesDecode) {
  const std::string ycbv = testing::YcbvDir();
  auto png = io::ReadColourImage(ycbv + "/data/0049/000001-color.png");
  ASSERT_TRUE(png.ok()) << png.status().ToString();
  EXPECT_EQ(png->width, 640);
  EXPECT_EQ(png->height, 480);
  auto jpeg = io::ReadColourImage(ycbv + "/models/003_cracker_box/texture_map.jpg");
  ASSERT_TRUE(jpeg.ok()) << jpeg.status().ToString();
  EXPECT_EQ(jpeg->width, 4096);
  // The cracker box's model carries its texture, reduced, with a texture coordinate per corner.
  auto mesh = io::ReadObjMesh(ycbv + "/models/003_cracker_box/textured_simple.obj");
  ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
  ASSERT_TRUE(mesh->appearance.has_texture());
  EXPECT_EQ(mesh->appearance.texture->width, io::kMaxTextureSide);
  EXPECT_EQ(mesh->appearance.triangle_uv.size(), mesh->triangles.size());
  // A model whose material file is missing (most of YCB-Video's) has no colour.
  auto plain = io::ReadObjMesh(ycbv + "/models/004_sugar_box/textured_simple.obj");
  ASSERT_TRUE(plain.ok());
  EXPECT_TRUE(plain->appearance.empty());
}

TEST(ColourIo, TruncatedOrForeignImagesAreOneClearError) {
  const fs::path dir = testing::TempDir("colour_io_bad");
  const std::string jpeg = Bytes(testing::YcbvDir() + "/models/003_cracker_box/texture_map.jpg");
  Write(dir / "half.jpg", jpeg.substr(0, jpeg.size() / 2));
  auto r = io::ReadColourImage((dir / "half.jpg").string());
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("half.jpg"), std::string::npos) << r.status().message();
  EXPECT_NE(r.status().message().find("truncated"), std::string::npos) << r.status().message();
  Write(dir / "text.png", "not an image");
  r = io::ReadColourImage((dir / "text.png").string());
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("not a PNG or JPEG"), std::string::npos);
  // 16-bit samples are not colour.
  r = io::ReadColourPng(testing::YcbvDir() + "/data/0049/000001-depth.png");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("8-bit"), std::string::npos) << r.status().message();
}

// A material naming a texture that does not exist: the model loads without colour. One that
// exists but is truncated: an error naming it.
TEST(ColourIo, MissingTextureMeansNoColourATruncatedOneIsAnError) {
  const fs::path dir = testing::TempDir("colour_io_texture");
  const std::string src = testing::YcbvDir() + "/models/003_cracker_box/";
  Write(dir / "textured_simple.obj", Bytes(src + "textured_simple.obj"));
  Write(dir / "textured_simple.obj.mtl", Bytes(src + "textured_simple.obj.mtl"));
  auto mesh = io::ReadObjMesh((dir / "textured_simple.obj").string());
  ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
  EXPECT_TRUE(mesh->appearance.empty());
  const std::string jpeg = Bytes(src + "texture_map.jpg");
  Write(dir / "texture_map.jpg", jpeg.substr(0, jpeg.size() / 3));
  mesh = io::ReadObjMesh((dir / "textured_simple.obj").string());
  ASSERT_FALSE(mesh.ok());
  EXPECT_NE(mesh.status().message().find("texture_map.jpg"), std::string::npos) << mesh.status().message();
}

TEST(ColourIo, PlyVertexColoursRoundTrip) {
  Mesh m = testing::Blob();
  for (size_t i = 0; i < m.vertices_m.size(); ++i)
    m.appearance.vertex_colours.push_back({static_cast<uint8_t>(i), static_cast<uint8_t>(3 * i), 200, i % 5 ? uint8_t{255} : uint8_t{0}});
  const fs::path p = testing::TempDir("ply_colour") / "m.ply";
  ASSERT_TRUE(io::WritePlyMesh(p.string(), m, 1000.0).ok());
  auto back = io::ReadPlyMesh(p.string(), 1000.0);
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  EXPECT_EQ(back->vertices_m, m.vertices_m);  // the same floats after mm and back
  EXPECT_EQ(back->triangles, m.triangles);
  EXPECT_EQ(back->appearance.vertex_colours, m.appearance.vertex_colours);
}

// A colour frame of another size than its depth image: an error naming the colour file.
TEST(ColourIo, ColourFrameOfAnotherSizeIsAnError) {
  const fs::path dir = testing::TempDir("colour_frame_size");
  const fs::path root = dir / "bop";
  fs::copy(testing::BopDir(), root, fs::copy_options::recursive);
  ColourImage small;
  small.width = 320, small.height = 240;
  small.rgba.assign(4 * 320 * 240, 255);
  const fs::path rgb = root / "test/000049/rgb/000001.png";
  fs::remove(rgb);
  ASSERT_TRUE(io::WriteColourPng(rgb.string(), small).ok());
  auto ds = Dataset::Open(root.string());
  ASSERT_TRUE(ds.ok());
  // Loading the frame checks the colour image's size, before any colour is decoded.
  auto frame = (*ds)->LoadFrame(FrameKey{49, 1});
  ASSERT_FALSE(frame.ok());
  EXPECT_NE(frame.status().message().find("rgb/000001.png"), std::string::npos) << frame.status().message();
  EXPECT_NE(frame.status().message().find("320x240"), std::string::npos);
  // A well-formed frame of the other layout loads, alpha opaque.
  auto ycbv = Dataset::Open(testing::YcbvDir());
  auto f = (*ycbv)->LoadFrame(FrameKey{49, 1});
  auto c = (*ycbv)->LoadColour(*f);
  ASSERT_TRUE(c.ok());
  EXPECT_EQ(c->at(0, 0)[3], 255);
}

TEST(ColourIo, SyntheticFramesLoadByNameButAreNotAmongTheFrames) {
  auto ds = Dataset::Open(testing::YcbvDir());
  ASSERT_TRUE(ds.ok());
  auto key = (*ds)->ParseFrameName("data_syn/000002");
  ASSERT_TRUE(key.ok()) << key.status().ToString();
  EXPECT_EQ(key->scene_id, kSyntheticScene);
  EXPECT_EQ((*ds)->FrameName(*key), "data_syn/000002");
  for (const FrameKey& k : (*ds)->Frames()) EXPECT_NE(k.scene_id, kSyntheticScene);
  auto frame = (*ds)->LoadFrame(*key);
  ASSERT_TRUE(frame.ok()) << frame.status().ToString();
  EXPECT_EQ(frame->gt.size(), 8u);
  EXPECT_TRUE((*ds)->LoadColour(*frame).ok());
  EXPECT_EQ((*ds)->FrameName(FrameKey{49, 1}), "0049/000001");
  EXPECT_FALSE((*ds)->ParseFrameName("0049/000099").ok());
  EXPECT_FALSE((*ds)->ParseFrameName("banana").ok());
}

}  // namespace
}  // namespace mcpose

#include "io/ycbv_dataset.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "io/ycbv_names.h"
#include "mcpose/dataset.h"
#include "test_data.h"

namespace mcpose {
namespace {

namespace fs = std::filesystem;

constexpr FrameKey kFrame{49, 1};

std::unique_ptr<Dataset> OpenOrDie(const std::string& root) {
  StatusOr<std::unique_ptr<Dataset>> dataset = Dataset::Open(root);
  EXPECT_TRUE(dataset.ok()) << dataset.status().ToString();
  return dataset.ok() ? std::move(dataset).value() : nullptr;
}

double Median(std::vector<float> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

TEST(YcbvDatasetIoTest, ListsRealFramesOnly) {
  auto dataset = OpenOrDie(testing::YcbvDir());
  ASSERT_TRUE(dataset);
  EXPECT_EQ(dataset->format(), DatasetFormat::kYcbv);
  const std::vector<FrameKey> frames = dataset->Frames();
  // 0000-0002: 5 frames each, 0003: 1, 0049: 10; data_syn/ is not a scene.
  EXPECT_EQ(frames.size(), 26u);
  EXPECT_TRUE(std::is_sorted(frames.begin(), frames.end()));
  EXPECT_EQ(frames.front(), (FrameKey{0, 1}));
  EXPECT_EQ(frames.back(), (FrameKey{49, 10}));
  EXPECT_NE(std::find(frames.begin(), frames.end(), (FrameKey{3, 138})), frames.end());
}

TEST(YcbvDatasetIoTest, LoadsTestKeyframe) {
  auto dataset = OpenOrDie(testing::YcbvDir());
  ASSERT_TRUE(dataset);
  StatusOr<Frame> frame = dataset->LoadFrame(kFrame);
  ASSERT_TRUE(frame.ok()) << frame.status().ToString();

  // Intrinsics (README) and image size.
  EXPECT_EQ(frame->K.fx, 1066.778);
  EXPECT_EQ(frame->K.fy, 1067.487);
  EXPECT_EQ(frame->K.cx, 312.9869);
  EXPECT_EQ(frame->K.cy, 241.3109);
  EXPECT_EQ(frame->K.width, 640);
  EXPECT_EQ(frame->K.height, 480);
  EXPECT_EQ(frame->depth.width, 640);
  EXPECT_EQ(frame->depth.height, 480);

  // Depth in metres: objects at 0.53-1.14 m; a few percent of the pixels missing.
  std::vector<float> valid;
  for (float d : frame->depth.depth_m) {
    if (d > 0) valid.push_back(d);
  }
  const double invalid_fraction = 1.0 - static_cast<double>(valid.size()) / (640 * 480);
  EXPECT_LT(invalid_fraction, 0.2);
  const double median_m = Median(valid);
  EXPECT_GT(median_m, 0.5);
  EXPECT_LT(median_m, 1.2);
  EXPECT_LT(*std::max_element(valid.begin(), valid.end()), 6.6f);

  // Ground truth: four objects in meta.mat order, poses in metres, rotations.
  ASSERT_EQ(frame->gt.size(), 4u);
  const int expected_ids[4] = {3, 6, 9, 13};
  for (int i = 0; i < 4; ++i) {
    const GtInstance& gt = frame->gt[i];
    EXPECT_EQ(gt.obj_id, expected_ids[i]);
    EXPECT_EQ(gt.gt_index, i);
    EXPECT_LT((gt.T_cam_obj.R.transpose() * gt.T_cam_obj.R - Eigen::Matrix3d::Identity()).norm(),
              1e-5);
    EXPECT_GT(gt.T_cam_obj.t.z(), 0.5);
    EXPECT_LT(gt.T_cam_obj.t.z(), 1.2);
  }
  EXPECT_NEAR(frame->gt[0].T_cam_obj.t.z(), 0.7836220561, 1e-9);  // scene_gt.json: 783.622 mm
}

TEST(YcbvDatasetIoTest, VisibleMaskIsLabelEqualsObjId) {
  auto dataset = OpenOrDie(testing::YcbvDir());
  ASSERT_TRUE(dataset);
  StatusOr<Frame> frame = dataset->LoadFrame(kFrame);
  ASSERT_TRUE(frame.ok());
  const size_t expected_pixels[4] = {27218, 7100, 11639, 10390};  // README
  for (int i = 0; i < 4; ++i) {
    StatusOr<MaskImage> mask = dataset->LoadVisibleMask(kFrame, frame->gt[i]);
    ASSERT_TRUE(mask.ok()) << mask.status().ToString();
    EXPECT_EQ(mask->width, 640);
    size_t inside = 0;
    for (uint8_t v : mask->values) {
      EXPECT_TRUE(v == 0 || v == 255);
      inside += (v != 0);
    }
    EXPECT_EQ(inside, expected_pixels[i]) << "obj " << frame->gt[i].obj_id;
  }

  // The mug of 0003/000138 lies outside the image: an all-zero mask is valid.
  StatusOr<Frame> edge = dataset->LoadFrame({3, 138});
  ASSERT_TRUE(edge.ok()) << edge.status().ToString();
  ASSERT_EQ(edge->gt.size(), 4u);
  EXPECT_EQ(edge->gt[2].obj_id, 14);
  StatusOr<MaskImage> mug = dataset->LoadVisibleMask({3, 138}, edge->gt[2]);
  ASSERT_TRUE(mug.ok());
  EXPECT_EQ(std::count(mug->values.begin(), mug->values.end(), 0), 640 * 480);
}

TEST(YcbvDatasetIoTest, ObjectsMeshesAndPoints) {
  auto dataset = OpenOrDie(testing::YcbvDir());
  ASSERT_TRUE(dataset);
  std::vector<int> ids = dataset->ObjectIds();
  ASSERT_EQ(ids.size(), 21u);
  EXPECT_EQ(ids.front(), 1);
  EXPECT_EQ(ids.back(), 21);
  for (int id : ids) EXPECT_EQ(dataset->ObjectName(id), io::YcbvClassNames()[id - 1]);
  EXPECT_EQ(dataset->ObjectName(3), "004_sugar_box");

  StatusOr<Mesh> mesh = dataset->LoadMesh(3);
  ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
  EXPECT_EQ(mesh->vertices_m.size(), 7866u);
  EXPECT_EQ(mesh->triangles.size(), 15728u);
  // Marker: 162 zero-area triangles among valid ones still validate.
  EXPECT_TRUE(dataset->LoadMesh(18).ok());

  StatusOr<std::vector<Eigen::Vector3f>> points = dataset->LoadEvalPoints(3);
  ASSERT_TRUE(points.ok()) << points.status().ToString();
  EXPECT_EQ(points->size(), 2621u);
  EXPECT_NEAR((*points)[0].x(), 0.021672f, 1e-7);
  // Points lie within the mesh bounds (plus the 0.7 mm surface distance of the README).
  for (const auto& p : *points) {
    EXPECT_TRUE((p.array() >= mesh->BoundsMin().array() - 1e-3f).all());
    EXPECT_TRUE((p.array() <= mesh->BoundsMax().array() + 1e-3f).all());
  }
  StatusOr<Mesh> unknown = dataset->LoadMesh(99);
  EXPECT_EQ(unknown.status().code(), StatusCode::kNotFound);
  EXPECT_EQ(dataset->LoadFrame({49, 11}).status().code(), StatusCode::kNotFound);
}

TEST(YcbvDatasetIoTest, ReadsSyntheticMetaTypes) {
  // data_syn: poses single, cls_indexes single 1xN, factor_depth double.
  const std::string path = testing::YcbvDir() + "/data_syn/000001-meta.mat";
  StatusOr<io::YcbvMeta> meta = io::ReadYcbvMeta(path);
  ASSERT_TRUE(meta.ok()) << meta.status().ToString();
  EXPECT_EQ(meta->cls_indexes, (std::vector<int>{18, 8, 20, 7, 11}));
  EXPECT_EQ(meta->poses.size(), 5u);
  EXPECT_EQ(meta->factor_depth, 10000);
  for (const SE3& T : meta->poses) {
    EXPECT_LT(std::abs(T.R.determinant() - 1), 1e-5);
  }
  EXPECT_NEAR(meta->K(0, 0), 1066.778, 1e-9);
  EXPECT_EQ(meta->K(2, 2), 1.0);
}

// A one-frame YCB-Video folder in a temp dir with a rewritten meta.mat.
std::string TempYcbv(const std::string& name, const io::YcbvMeta& meta) {
  const fs::path root = testing::TempDir(name);
  const fs::path src = testing::YcbvDir();
  fs::create_directories(root / "data/0049");
  fs::copy_file(src / "classes.txt", root / "classes.txt");
  fs::copy_file(src / "data/0049/000001-depth.png", root / "data/0049/000001-depth.png");
  fs::copy_file(src / "data/0049/000001-label.png", root / "data/0049/000001-label.png");
  EXPECT_TRUE(io::WriteYcbvMeta((root / "data/0049/000001-meta.mat").string(), meta).ok());
  return root.string();
}

TEST(YcbvDatasetIoTest, MetaWriteReadRoundTrip) {
  StatusOr<io::YcbvMeta> meta = io::ReadYcbvMeta(testing::YcbvDir() + "/data/0049/000001-meta.mat");
  ASSERT_TRUE(meta.ok());
  const std::string root = TempYcbv("ycbv_roundtrip", *meta);
  StatusOr<io::YcbvMeta> back = io::ReadYcbvMeta(root + "/data/0049/000001-meta.mat");
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  EXPECT_EQ(back->K, meta->K);
  EXPECT_EQ(back->cls_indexes, meta->cls_indexes);
  ASSERT_EQ(back->poses.size(), meta->poses.size());
  EXPECT_EQ(back->poses[2].R, meta->poses[2].R);
  EXPECT_EQ(back->poses[2].t, meta->poses[2].t);

  auto dataset = OpenOrDie(root);
  ASSERT_TRUE(dataset);
  EXPECT_EQ(dataset->Frames(), (std::vector<FrameKey>{kFrame}));
  EXPECT_TRUE(dataset->LoadFrame(kFrame).ok());
  // No models in this copy: no object ids, and meshes are NotFound.
  EXPECT_TRUE(dataset->ObjectIds().empty());
  EXPECT_EQ(dataset->LoadMesh(3).status().code(), StatusCode::kNotFound);

  // A single pose (N = 1) is written 3x4x1 and may be read back as 3x4.
  io::YcbvMeta one = *meta;
  one.poses.resize(1);
  one.cls_indexes.resize(1);
  const std::string one_path = root + "/one-meta.mat";
  ASSERT_TRUE(io::WriteYcbvMeta(one_path, one).ok());
  StatusOr<io::YcbvMeta> one_back = io::ReadYcbvMeta(one_path);
  ASSERT_TRUE(one_back.ok()) << one_back.status().ToString();
  EXPECT_EQ(one_back->poses.size(), 1u);
}

TEST(YcbvDatasetIoTest, BadIntrinsicsNameTheMetaFile) {
  StatusOr<io::YcbvMeta> meta = io::ReadYcbvMeta(testing::YcbvDir() + "/data/0049/000001-meta.mat");
  ASSERT_TRUE(meta.ok());
  struct Case {
    const char* name;
    double fx;
    const char* message;
  } cases[] = {{"ycbv_nan_k", std::numeric_limits<double>::quiet_NaN(), "non-finite"},
               {"ycbv_zero_k", 0.0, "fx = 0 px is outside 1-100000 px"}};
  for (const Case& c : cases) {
    io::YcbvMeta bad = *meta;
    bad.K(0, 0) = c.fx;
    const std::string root = TempYcbv(c.name, bad);
    auto dataset = OpenOrDie(root);
    ASSERT_TRUE(dataset);
    const Status status = dataset->LoadFrame(kFrame).status();
    EXPECT_EQ(status.code(), StatusCode::kInvalidArgument);
    EXPECT_NE(status.message().find("000001-meta.mat"), std::string::npos) << status.message();
    EXPECT_NE(status.message().find(c.message), std::string::npos) << status.message();
  }
  // All-zero matrix.
  io::YcbvMeta zero = *meta;
  zero.K.setZero();
  auto dataset = OpenOrDie(TempYcbv("ycbv_all_zero_k", zero));
  ASSERT_TRUE(dataset);
  const Status status = dataset->LoadFrame(kFrame).status();
  EXPECT_NE(status.message().find("000001-meta.mat: intrinsic_matrix"), std::string::npos)
      << status.message();
}

TEST(YcbvDatasetIoTest, BadFilesNameTheFile) {
  StatusOr<io::YcbvMeta> meta = io::ReadYcbvMeta(testing::YcbvDir() + "/data/0049/000001-meta.mat");
  ASSERT_TRUE(meta.ok());
  const std::string root = TempYcbv("ycbv_bad_files", *meta);
  auto dataset = OpenOrDie(root);
  ASSERT_TRUE(dataset);
  const std::string depth = root + "/data/0049/000001-depth.png";

  // 8-bit depth.
  fs::copy_file(root + "/data/0049/000001-label.png", depth, fs::copy_options::overwrite_existing);
  Status status = dataset->LoadFrame(kFrame).status();
  EXPECT_NE(status.message().find(depth + ": depth PNG must be 16-bit single-channel, got 8-bit"),
            std::string::npos)
      << status.message();

  // Missing depth.
  fs::remove(depth);
  status = dataset->LoadFrame(kFrame).status();
  EXPECT_EQ(status.code(), StatusCode::kNotFound);
  EXPECT_NE(status.message().find(depth), std::string::npos) << status.message();

  // A MAT-file without poses, and a file that is not a MAT-file.
  const std::string meta_path = root + "/data/0049/000001-meta.mat";
  fs::copy_file(testing::YcbvDir() + "/data/0049/000001-label.png", meta_path,
                fs::copy_options::overwrite_existing);
  status = io::ReadYcbvMeta(meta_path).status();
  EXPECT_FALSE(status.ok());
  EXPECT_NE(status.message().find(meta_path), std::string::npos) << status.message();
  EXPECT_EQ(io::ReadYcbvMeta(root + "/none-meta.mat").status().code(), StatusCode::kNotFound);

  // Missing root.
  StatusOr<std::unique_ptr<Dataset>> missing = Dataset::Open(root + "/nope");
  EXPECT_EQ(missing.status().code(), StatusCode::kNotFound);
  EXPECT_NE(missing.status().message().find(root + "/nope"), std::string::npos);
}

}  // namespace
// A fuzzer's input (scripts/fuzz.sh, meta_mat): a compressed variable whose inflated dimensions
// tag claims 4.2 GB (in a stream that is corrupt further on) made libmatio allocate 8.5 GB.
// Refused before libmatio opens it, naming the file.
TEST(YcbvDatasetIoTest, CompressedVariableClaimingHugeDimensionsIsRefusedBeforeLibmatio) {
  const std::string hex =
      "4d41544c4142dbca2e30204d41542d66696c652c20506c6154666f726d3a20474c4e584136342c204372656174656420"
      "6f6e3a2053756e205365702031302030343a34393a313720323031372020202020202020202020202020202020202020"
      "202020202020202220202020202020202020202000000000000000000001494d0f00000033000000789ce36360607000"
      "623620e680d220c00ae5b300312314730371724e717c665e4a6a456a31581d135005331b272f00752e05370f00000033"
      "000000789ce36360607000623620e680d220c00aa1eb0000806000004c2ec9c875b0b6c10914f3006275438e3532ab00"
      "008077030000ffffecc1010d100000c2a0f74f6d0e37a000000000e94ea7dd1db86fef94dccee93ac8860a8ee5b2a97c"
      "2236469e925cfebd4f5f6dab87df03d7d0ff1b728575f59705f2b14c943e729dfceeefab64aa0c94fed1cf91325d3e95"
      "4c9e689853a49cd742a6c9a2";
  std::string bytes;
  for (size_t i = 0; i + 1 < hex.size(); i += 2) bytes.push_back(static_cast<char>(std::stoi(hex.substr(i, 2), nullptr, 16)));
  const std::string path = (std::filesystem::temp_directory_path() / "mcpose_fuzz_meta_oom.mat").string();
  {
    std::ofstream f(path, std::ios::binary);
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  const StatusOr<io::YcbvMeta> meta = io::ReadYcbvMeta(path);
  ASSERT_FALSE(meta.ok());
  EXPECT_NE(meta.status().message().find(path), std::string::npos) << meta.status().message();
  EXPECT_NE(meta.status().message().find("does not inflate"), std::string::npos) << meta.status().message();
  std::filesystem::remove(path);
}

}  // namespace mcpose

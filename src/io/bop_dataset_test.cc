#include "io/bop_dataset.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "mcpose/io_util.h"
#include "io/ycbv_names.h"
#include "mcpose/dataset.h"
#include "test_data.h"

namespace mcpose {
namespace {

namespace fs = std::filesystem;

std::unique_ptr<Dataset> OpenOrDie(const std::string& root, const std::string& split = "test") {
  StatusOr<std::unique_ptr<Dataset>> dataset = Dataset::Open(root, split);
  EXPECT_TRUE(dataset.ok()) << dataset.status().ToString();
  return dataset.ok() ? std::move(dataset).value() : nullptr;
}

TEST(BopDatasetIoTest, ListsFramesOfTheSplit) {
  auto test = OpenOrDie(testing::BopDir());
  ASSERT_TRUE(test);
  EXPECT_EQ(test->format(), DatasetFormat::kBop);
  EXPECT_EQ(test->Frames(),
            (std::vector<FrameKey>{{49, 1}, {49, 2}, {49, 3}, {49, 4}, {49, 5}}));
  auto train = OpenOrDie(testing::BopDir(), "train_real");
  ASSERT_TRUE(train);
  EXPECT_EQ(train->Frames().size(), 5u);
  EXPECT_EQ(train->Frames().front(), (FrameKey{1, 1}));

  StatusOr<std::unique_ptr<Dataset>> none = Dataset::Open(testing::BopDir(), "val");
  EXPECT_EQ(none.status().code(), StatusCode::kNotFound);
  EXPECT_NE(none.status().message().find("'val'"), std::string::npos) << none.status().message();
}

TEST(BopDatasetIoTest, ObjectsUseYcbvNames) {
  auto dataset = OpenOrDie(testing::BopDir());
  ASSERT_TRUE(dataset);
  ASSERT_EQ(dataset->ObjectIds().size(), 21u);
  EXPECT_EQ(dataset->ObjectName(1), "002_master_chef_can");
  EXPECT_EQ(dataset->ObjectName(21), "061_foam_brick");
  StatusOr<std::vector<Eigen::Vector3f>> points = dataset->LoadEvalPoints(3);
  ASSERT_TRUE(points.ok()) << points.status().ToString();
  EXPECT_EQ(points->size(), 7866u);  // BOP: the model vertices
  EXPECT_EQ(dataset->LoadMesh(22).status().code(), StatusCode::kNotFound);
}

// BOP test/000049 image 1 is YCB-Video data/0049/000001: both readers must agree.
TEST(BopDatasetIoTest, AgreesWithNativeYcbv) {
  auto bop = OpenOrDie(testing::BopDir());
  auto ycbv = OpenOrDie(testing::YcbvDir());
  ASSERT_TRUE(bop && ycbv);
  double max_dR = 0, max_dt_m = 0;
  for (int im_id = 1; im_id <= 5; ++im_id) {
    const FrameKey key{49, im_id};
    StatusOr<Frame> a = bop->LoadFrame(key);
    StatusOr<Frame> b = ycbv->LoadFrame(key);
    ASSERT_TRUE(a.ok()) << a.status().ToString();
    ASSERT_TRUE(b.ok()) << b.status().ToString();

    // Intrinsics and depth floats identical.
    EXPECT_EQ(a->K.fx, b->K.fx);
    EXPECT_EQ(a->K.fy, b->K.fy);
    EXPECT_EQ(a->K.cx, b->K.cx);
    EXPECT_EQ(a->K.cy, b->K.cy);
    EXPECT_EQ(a->K.width, b->K.width);
    EXPECT_EQ(a->K.height, b->K.height);
    EXPECT_TRUE(a->depth.depth_m == b->depth.depth_m) << "depth floats differ, image " << im_id;

    // Ground truth: same objects, same poses.
    ASSERT_EQ(a->gt.size(), b->gt.size());
    for (size_t i = 0; i < a->gt.size(); ++i) {
      EXPECT_EQ(a->gt[i].obj_id, b->gt[i].obj_id);
      EXPECT_EQ(a->gt[i].gt_index, b->gt[i].gt_index);
      max_dR = std::max(max_dR, (a->gt[i].T_cam_obj.R - b->gt[i].T_cam_obj.R).cwiseAbs().maxCoeff());
      max_dt_m =
          std::max(max_dt_m, (a->gt[i].T_cam_obj.t - b->gt[i].T_cam_obj.t).cwiseAbs().maxCoeff());

      // mask_visib == (label.png == obj_id).
      StatusOr<MaskImage> ma = bop->LoadVisibleMask(key, a->gt[i]);
      StatusOr<MaskImage> mb = ycbv->LoadVisibleMask(key, b->gt[i]);
      ASSERT_TRUE(ma.ok()) << ma.status().ToString();
      ASSERT_TRUE(mb.ok()) << mb.status().ToString();
      EXPECT_EQ(ma->values, mb->values) << "image " << im_id << " instance " << i;
    }
  }
  std::printf("[BopDatasetIoTest] BOP vs native GT, 5 frames: max |dR| = %.3g, max |dt| = %.3g m\n",
              max_dR, max_dt_m);
  EXPECT_LT(max_dR, 1e-9);
  EXPECT_LT(max_dt_m, 1e-9);
}

TEST(BopDatasetIoTest, MeshesMatchNativeObj) {
  auto bop = OpenOrDie(testing::BopDir());
  auto ycbv = OpenOrDie(testing::YcbvDir());
  ASSERT_TRUE(bop && ycbv);
  for (int obj_id : {1, 3, 13, 18}) {
    StatusOr<Mesh> a = bop->LoadMesh(obj_id);
    StatusOr<Mesh> b = ycbv->LoadMesh(obj_id);
    ASSERT_TRUE(a.ok()) << a.status().ToString();
    ASSERT_TRUE(b.ok()) << b.status().ToString();
    ASSERT_EQ(a->vertices_m.size(), b->vertices_m.size());
    EXPECT_EQ(a->triangles, b->triangles);
    float max_diff = 0;
    for (size_t i = 0; i < a->vertices_m.size(); ++i) {
      max_diff = std::max(max_diff, (a->vertices_m[i] - b->vertices_m[i]).cwiseAbs().maxCoeff());
    }
    EXPECT_LT(max_diff, 1e-7f) << "obj " << obj_id;
  }
}

// A one-frame BOP folder in a temp dir: copies of the files needed, scene_camera.json rewritten.
struct TempBop {
  fs::path root;
  fs::path scene;
};

TempBop MakeTempBop(const std::string& name, const std::string& scene_camera_text) {
  TempBop bop{testing::TempDir(name), {}};
  const fs::path src = testing::BopDir();
  bop.scene = bop.root / "test/000049";
  fs::create_directories(bop.root / "models");
  fs::create_directories(bop.scene / "depth");
  fs::create_directories(bop.scene / "mask_visib");
  fs::copy_file(src / "models/models_info.json", bop.root / "models/models_info.json");
  for (const auto& e : fs::directory_iterator(src / "models"))
    if (e.path().extension() == ".ply") fs::create_symlink(e.path(), bop.root / "models" / e.path().filename());
  fs::copy_file(src / "camera.json", bop.root / "camera.json");
  fs::copy_file(src / "test/000049/depth/000001.png", bop.scene / "depth/000001.png");
  // scene_gt.json restricted to image 1.
  std::ifstream in(src / "test/000049/scene_gt.json");
  nlohmann::json gt = nlohmann::json::parse(in);
  std::ofstream(bop.scene / "scene_gt.json") << nlohmann::json{{"1", gt["1"]}}.dump();
  std::ofstream(bop.scene / "scene_camera.json") << scene_camera_text;
  return bop;
}

const char* kCameraOk =
    R"({"1": {"cam_K": [1066.778, 0.0, 312.9869, 0.0, 1067.487, 241.3109, 0.0, 0.0, 1.0],)"
    R"( "depth_scale": 0.1}})";

TEST(BopDatasetIoTest, TempCopyLoads) {
  TempBop bop = MakeTempBop("bop_ok", kCameraOk);
  auto dataset = OpenOrDie(bop.root.string());
  ASSERT_TRUE(dataset);
  StatusOr<Frame> frame = dataset->LoadFrame({49, 1});
  ASSERT_TRUE(frame.ok()) << frame.status().ToString();
  EXPECT_EQ(frame->gt.size(), 4u);
  // Missing mask and missing model name their files.
  StatusOr<MaskImage> mask = dataset->LoadVisibleMask({49, 1}, frame->gt[0]);
  EXPECT_EQ(mask.status().code(), StatusCode::kNotFound);
  EXPECT_NE(mask.status().message().find("mask_visib/000001_000000.png"), std::string::npos);
  // A model that models_info.json lists but that is missing: the dataset does not open.
  fs::remove(bop.root / "models/obj_000003.ply");
  const Status missing = Dataset::Open(bop.root.string()).status();
  EXPECT_NE(missing.message().find("models_info.json: key '3' names no model file"), std::string::npos)
      << missing.message();
  EXPECT_NE(missing.message().find("obj_000003.ply"), std::string::npos) << missing.message();
}

TEST(BopDatasetIoTest, BadIntrinsicsNameTheFile) {
  struct Case {
    const char* name;
    const char* camera;
    const char* message;
  } cases[] = {
      {"bop_zero_k", R"({"1": {"cam_K": [0, 0, 0, 0, 0, 0, 0, 0, 0], "depth_scale": 0.1}})",
       "fx = 0 px is outside 1-100000 px"},
      {"bop_nan_k",
       R"({"1": {"cam_K": [NaN, 0.0, 312.9, 0.0, 1067.4, 241.3, 0.0, 0.0, 1.0], "depth_scale": 0.1}})",
       "NaN"},
      {"bop_inf_k",
       R"({"1": {"cam_K": [1e999, 0.0, 312.9, 0.0, 1067.4, 241.3, 0.0, 0.0, 1.0], "depth_scale": 0.1}})",
       "number overflow"},  // nlohmann/json refuses out-of-range numbers
      {"bop_short_k", R"({"1": {"cam_K": [1066.778, 0.0, 312.9869], "depth_scale": 0.1}})",
       "cam_K must have 9 numbers"},
      {"bop_no_scale", R"({"1": {"cam_K": [1066.778, 0.0, 312.9869, 0.0, 1067.487, 241.3109, 0, 0, 1]}})",
       ""},
      {"bop_missing_image", R"({"2": {"cam_K": [1, 0, 1, 0, 1, 1, 0, 0, 1], "depth_scale": 0.1}})",
       "no entry for image 1"},
  };
  for (const Case& c : cases) {
    TempBop bop = MakeTempBop(c.name, c.camera);
    auto dataset = OpenOrDie(bop.root.string());
    ASSERT_TRUE(dataset);
    const Status status = dataset->LoadFrame({49, 1}).status();
    if (std::string(c.name) == "bop_no_scale") {
      // camera.json supplies depth_scale 0.1.
      EXPECT_TRUE(status.ok()) << status.ToString();
      continue;
    }
    EXPECT_FALSE(status.ok()) << c.name;
    EXPECT_NE(status.message().find((bop.scene / "scene_camera.json").string()), std::string::npos)
        << status.message();
    EXPECT_NE(status.message().find(c.message), std::string::npos) << status.message();
  }
}

TEST(BopDatasetIoTest, DepthSizeMustMatchCamera) {
  TempBop bop = MakeTempBop("bop_depth_size", kCameraOk);
  std::ofstream(bop.root / "camera.json") << R"({"width": 320, "height": 240, "depth_scale": 0.1})";
  auto dataset = OpenOrDie(bop.root.string());
  ASSERT_TRUE(dataset);
  const Status status = dataset->LoadFrame({49, 1}).status();
  EXPECT_NE(status.message().find("depth/000001.png: depth image is 640x480"), std::string::npos)
      << status.message();
}

TEST(BopDatasetIoTest, BadSceneGtNamesFileAndEntry) {
  TempBop bop = MakeTempBop("bop_bad_gt", kCameraOk);
  std::ofstream(bop.scene / "scene_gt.json")
      << R"({"1": [{"obj_id": 3, "cam_R_m2c": [1, 0, 0, 0, 1, 0, 0, 0, 1], "cam_t_m2c": [0, 0]}]})";
  StatusOr<std::unique_ptr<Dataset>> dataset = Dataset::Open(bop.root.string());
  ASSERT_FALSE(dataset.ok());
  EXPECT_NE(dataset.status().message().find("scene_gt.json: image 1: entry 0: cam_t_m2c"),
            std::string::npos)
      << dataset.status().message();

  std::ofstream(bop.scene / "scene_gt.json") << R"({"1": [)";
  dataset = Dataset::Open(bop.root.string());
  ASSERT_FALSE(dataset.ok());
  EXPECT_EQ(dataset.status().code(), StatusCode::kDataLoss);
  EXPECT_NE(dataset.status().message().find("scene_gt.json: malformed JSON"), std::string::npos)
      << dataset.status().message();
}

TEST(BopDatasetIoTest, OpenErrorsNameTheFolder) {
  const fs::path empty = testing::TempDir("bop_not_a_dataset");
  StatusOr<std::unique_ptr<Dataset>> dataset = Dataset::Open(empty.string());
  EXPECT_EQ(dataset.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(dataset.status().message().find(empty.string() + ": not a dataset folder"),
            std::string::npos)
      << dataset.status().message();

  dataset = Dataset::Open("/nonexistent/mcpose/dataset");
  EXPECT_EQ(dataset.status().code(), StatusCode::kNotFound);
  EXPECT_NE(dataset.status().message().find("/nonexistent/mcpose/dataset"), std::string::npos);
}

TEST(BopDatasetIoTest, NonYcbvIdsGetBopNames) {
  TempBop bop = MakeTempBop("bop_names", kCameraOk);
  std::ofstream(bop.root / "models/models_info.json")
      << R"({"3": {"diameter": 1.0}, "30": {"diameter": 2.0}})";
  fs::copy_file(bop.root / "models/obj_000003.ply", bop.root / "models/obj_000030.ply");
  auto dataset = OpenOrDie(bop.root.string());
  ASSERT_TRUE(dataset);
  EXPECT_EQ(dataset->ObjectIds(), (std::vector<int>{3, 30}));
  EXPECT_EQ(dataset->ObjectName(3), "obj_000003");
  EXPECT_EQ(dataset->ObjectName(30), "obj_000030");
}

}  // namespace
}  // namespace mcpose

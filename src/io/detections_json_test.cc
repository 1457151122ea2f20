#include "mcpose/detection.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "test_data.h"

namespace mcpose {
namespace {

std::string WriteText(const std::string& test, const std::string& text) {
  const std::string path = (testing::TempDir(test) / "dets.json").string();
  std::ofstream(path) << text;
  return path;
}

void ExpectError(const std::string& path, const std::string& what) {
  StatusOr<std::vector<Detection>> dets = ReadDetectionsJson(path);
  ASSERT_FALSE(dets.ok()) << what;
  EXPECT_NE(dets.status().message().find(path), std::string::npos) << dets.status().message();
  EXPECT_NE(dets.status().message().find(what), std::string::npos) << dets.status().message();
}

TEST(DetectionsJsonIoTest, ReadsBopFormat) {
  const std::string path = WriteText(
      "dets_read",
      R"([{"scene_id": 48, "image_id": 1, "category_id": 1, "score": 0.98, "bbox": [10.5, 20, 30, 40], "time": 0.12},
          {"scene_id": 48, "image_id": 1, "category_id": 14, "score": 1, "bbox": [0, 0, 1, 2], "time": null},
          {"scene_id": 49, "image_id": 2, "category_id": 3.0, "score": 0.5, "bbox": [1, 2, 3, 4]}])");
  StatusOr<std::vector<Detection>> dets = ReadDetectionsJson(path);
  ASSERT_TRUE(dets.ok()) << dets.status().ToString();
  ASSERT_EQ(dets->size(), 3u);
  const Detection& d = (*dets)[0];
  EXPECT_EQ(d.scene_id, 48);
  EXPECT_EQ(d.image_id, 1);
  EXPECT_EQ(d.obj_id, 1);
  EXPECT_EQ(d.score, 0.98);
  EXPECT_EQ(d.x, 10.5);
  EXPECT_EQ(d.y, 20);
  EXPECT_EQ(d.w, 30);
  EXPECT_EQ(d.h, 40);
  EXPECT_EQ(d.time_s, 0.12);
  EXPECT_EQ((*dets)[1].time_s, -1);
  EXPECT_EQ((*dets)[2].obj_id, 3);
  EXPECT_EQ((*dets)[2].time_s, -1);
}

TEST(DetectionsJsonIoTest, RoundTrip) {
  std::vector<Detection> dets = {{48, 1, 1, 0.123456789012345, 1.25, 2.5, 30.125, 40.0625, 0.5},
                                 {59, 1000, 21, 1.0, 0, 0, 639.999, 479.5, -1}};
  const std::string path = (testing::TempDir("dets_roundtrip") / "dets.json").string();
  ASSERT_TRUE(WriteDetectionsJson(path, dets).ok());
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  StatusOr<std::vector<Detection>> back = ReadDetectionsJson(path);
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  ASSERT_EQ(back->size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    const Detection& a = dets[i];
    const Detection& b = (*back)[i];
    EXPECT_EQ(a.scene_id, b.scene_id);
    EXPECT_EQ(a.image_id, b.image_id);
    EXPECT_EQ(a.obj_id, b.obj_id);
    EXPECT_EQ(a.score, b.score);
    EXPECT_EQ(a.x, b.x);
    EXPECT_EQ(a.y, b.y);
    EXPECT_EQ(a.w, b.w);
    EXPECT_EQ(a.h, b.h);
    EXPECT_EQ(a.time_s, b.time_s);
  }
  // Empty list.
  ASSERT_TRUE(WriteDetectionsJson(path, {}).ok());
  back = ReadDetectionsJson(path);
  ASSERT_TRUE(back.ok());
  EXPECT_TRUE(back->empty());
}

TEST(DetectionsJsonIoTest, WriteRefusesInvalidAndLeavesNoFile) {
  const std::string path = (testing::TempDir("dets_write_bad") / "dets.json").string();
  std::vector<Detection> dets = {{48, 1, 1, 0.5, 0, 0, -3, 4, -1}};
  const Status status = WriteDetectionsJson(path, dets);
  EXPECT_EQ(status.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(status.message().find("detection 0"), std::string::npos) << status.message();
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
}

TEST(DetectionsJsonIoTest, MalformedJson) {
  const std::string path = WriteText("dets_malformed", R"([{"scene_id": 48, "image_id": )");
  ExpectError(path, "malformed JSON");
  ExpectError(path, "parse error");
  EXPECT_EQ(ReadDetectionsJson(path).status().code(), StatusCode::kDataLoss);
  ExpectError(WriteText("dets_not_list", R"({"scene_id": 48})"), "expected a JSON list");
  EXPECT_EQ(ReadDetectionsJson("/nonexistent/mcpose/dets.json").status().code(),
            StatusCode::kNotFound);
}

TEST(DetectionsJsonIoTest, BadEntriesNameTheIndex) {
  const std::string ok =
      R"({"scene_id": 48, "image_id": 1, "category_id": 1, "score": 0.9, "bbox": [1, 2, 3, 4]})";
  struct Case {
    const char* entry;
    const char* message;
  } cases[] = {
      {R"({"scene_id": 48, "image_id": 1, "category_id": 1, "score": 0.9, "bbox": [1, 2, 3]})",
       "entry 3: bbox must have 4 numbers"},
      {R"({"scene_id": 48, "image_id": 1, "category_id": 1, "score": 0.9, "bbox": [1, 2, "3", 4]})",
       "entry 3: bbox must have 4 numbers"},
      {R"({"scene_id": 48, "image_id": 1, "category_id": 1, "score": 0.9, "bbox": [1, 2, 0, 4]})",
       "entry 3: bbox width and height must be positive"},
      {R"({"scene_id": 48, "image_id": 1, "category_id": 1, "score": 1.5, "bbox": [1, 2, 3, 4]})",
       "entry 3: score must be a finite number in [0, 1]"},
      {R"({"scene_id": 48, "image_id": 1, "category_id": 1, "bbox": [1, 2, 3, 4]})",
       "entry 3: missing key 'score'"},
      {R"({"scene_id": 48, "image_id": 1.5, "category_id": 1, "score": 0.9, "bbox": [1, 2, 3, 4]})",
       "entry 3: 'image_id' must be an integer"},
      {R"({"scene_id": "48", "image_id": 1, "category_id": 1, "score": 0.9, "bbox": [1, 2, 3, 4]})",
       "entry 3: 'scene_id' must be an integer"},
      {R"({"scene_id": 48, "image_id": 1, "category_id": 0, "score": 0.9, "bbox": [1, 2, 3, 4]})",
       "entry 3: category_id must be a positive integer"},
      {R"({"scene_id": 48, "image_id": 1, "category_id": 1, "score": 0.9, "bbox": [1, 2, 3, 4], "time": "x"})",
       "entry 3: time must be a finite number"},
      {R"([1, 2])", "entry 3: expected an object"},
  };
  for (const Case& c : cases) {
    const std::string path =
        WriteText("dets_bad_entry", "[" + ok + "," + ok + "," + ok + "," + c.entry + "]");
    ExpectError(path, c.message);
  }
}

}  // namespace
}  // namespace mcpose

#include "mcpose/results.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "mcpose/io_util.h"
#include "test_data.h"

namespace mcpose {
namespace {

std::string WriteText(const std::string& test, const std::string& text) {
  const std::string path = (testing::TempDir(test) / "results.csv").string();
  std::ofstream(path) << text;
  return path;
}

TEST(ResultsCsvIoTest, RoundTrip) {
  // A rotation with irrational entries and a translation with sub-micrometre digits.
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  std::vector<PoseResult> results = {
      {48, 1, 1, 0.987654321, SE3(R, Eigen::Vector3d(0.0214871441, -0.0122884719, 0.7836220561)),
       0.25},
      {59, 1000, 21, 0, SE3(), -1},
  };
  const std::string path = (testing::TempDir("results_roundtrip") / "results.csv").string();
  ASSERT_TRUE(WriteResultsCsv(path, results).ok());
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));

  StatusOr<std::string> text = io::ReadFileToString(path);
  ASSERT_TRUE(text.ok());
  EXPECT_EQ(text->substr(0, text->find('\n')), "scene_id,im_id,obj_id,score,R,t,time");
  EXPECT_NE(text->find(",-1\n"), std::string::npos) << *text;

  StatusOr<std::vector<PoseResult>> back = ReadResultsCsv(path);
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  ASSERT_EQ(back->size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    const PoseResult& a = results[i];
    const PoseResult& b = (*back)[i];
    EXPECT_EQ(a.scene_id, b.scene_id);
    EXPECT_EQ(a.im_id, b.im_id);
    EXPECT_EQ(a.obj_id, b.obj_id);
    EXPECT_NEAR(a.score, b.score, 1e-9);
    EXPECT_LT((a.T_cam_obj.R - b.T_cam_obj.R).cwiseAbs().maxCoeff(), 1e-8);
    EXPECT_LT((a.T_cam_obj.t - b.T_cam_obj.t).cwiseAbs().maxCoeff(), 1e-9);  // 1 nm: %.6f mm
    EXPECT_NEAR(a.time_s, b.time_s, 1e-6);
  }
}

TEST(ResultsCsvIoTest, ReadsBopToolkitStyle) {
  // CRLF endings, a trailing empty line, spaces around fields.
  const std::string path = WriteText(
      "results_bop",
      "scene_id,im_id,obj_id,score,R,t,time\r\n"
      "48,1,2, 0.5 ,1 0 0 0 1 0 0 0 1,10 -20 800.5, 1.25\r\n"
      "\r\n");
  StatusOr<std::vector<PoseResult>> results = ReadResultsCsv(path);
  ASSERT_TRUE(results.ok()) << results.status().ToString();
  ASSERT_EQ(results->size(), 1u);
  EXPECT_EQ((*results)[0].T_cam_obj.t, Eigen::Vector3d(0.01, -0.02, 0.8005));
  EXPECT_EQ((*results)[0].time_s, 1.25);
}

TEST(ResultsCsvIoTest, BadLinesNameFileAndLine) {
  const std::string header = "scene_id,im_id,obj_id,score,R,t,time\n";
  const std::string good = "48,1,2,0.5,1 0 0 0 1 0 0 0 1,10 -20 800,1\n";
  struct Case {
    const char* line;
    const char* message;
  } cases[] = {
      {"48,1,2,0.5,1 0 0 0 1 0 0 0 1,10 -20 800\n", "line 3: expected 7 comma-separated fields, got 6"},
      {"48,1,2,0.5,1 0 0 0 1 0 0 0,10 -20 800,1\n", "line 3: R must be 9"},
      {"48,1,2,0.5,1 0 0 0 1 0 0 0 1,10 -20 nan,1\n", "line 3: t must be 3"},
      {"48,x,2,0.5,1 0 0 0 1 0 0 0 1,10 -20 800,1\n", "line 3: im_id is not an integer"},
      {"48,1,2,high,1 0 0 0 1 0 0 0 1,10 -20 800,1\n", "line 3: score is not a finite number"},
      {"48,1,2,0.5,1 0 0 0 1 0 0 0 1,10 -20 800,soon\n", "line 3: time is not a finite number"},
      {"48,1,2,0.5,2 0 0 0 1 0 0 0 1,10 -20 800,1\n", "line 3: R is not a rotation: max |R^T R - I| = 3,"},
      {"48,1,2,0.5,-1 0 0 0 1 0 0 0 1,10 -20 800,1\n", "line 3: R is not a rotation: max |R^T R - I| = 0, det = -1"},
  };
  for (const Case& c : cases) {
    const std::string path = WriteText("results_bad", header + good + c.line);
    StatusOr<std::vector<PoseResult>> results = ReadResultsCsv(path);
    ASSERT_FALSE(results.ok()) << c.line;
    EXPECT_NE(results.status().message().find(path + ": " + c.message), std::string::npos)
        << results.status().message();
  }
  const std::string path = WriteText("results_no_header", good);
  EXPECT_NE(ReadResultsCsv(path).status().message().find(path + ": line 1: expected the header"),
            std::string::npos);
  EXPECT_EQ(ReadResultsCsv("/nonexistent/mcpose/r.csv").status().code(), StatusCode::kNotFound);
}

TEST(ResultsCsvIoTest, WriteRefusesNonFinite) {
  const std::string path = (testing::TempDir("results_nan") / "results.csv").string();
  PoseResult r;
  r.T_cam_obj.t.x() = std::nan("");
  EXPECT_EQ(WriteResultsCsv(path, {r}).code(), StatusCode::kInvalidArgument);
  EXPECT_FALSE(std::filesystem::exists(path));
}

}  // namespace
}  // namespace mcpose

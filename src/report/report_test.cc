#include "mcpose/report.h"

#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>

#include <gtest/gtest.h>

#include "eval/fake_dataset_test_util.h"
#include "mcpose/io_util.h"
#include "test_data.h"

namespace mcpose::report {
namespace {

namespace fs = std::filesystem;
using eval_testing::FakeDataset;
using eval_testing::RectMask;

TEST(Report, AccuracyCurveIsAStaircaseOfSharesBelow) {
  // Errors 1, 3, 3 cm and a miss; the curve runs to 10 cm.
  const auto curve = AccuracyCurve({0.03, 0.01, INFINITY, 0.03}, 0.10);
  const std::vector<std::array<double, 2>> expected = {
      {0, 0}, {0.01, 0}, {0.01, 0.25}, {0.03, 0.25}, {0.03, 0.75}, {0.10, 0.75}};
  EXPECT_EQ(curve, expected);
  // Errors beyond the range never count; no errors: a flat zero.
  EXPECT_EQ(AccuracyCurve({0.2}, 0.1), (std::vector<std::array<double, 2>>{{0, 0}, {0.1, 0}}));
  EXPECT_EQ(AccuracyCurve({}, 0.1), (std::vector<std::array<double, 2>>{{0, 0}, {0.1, 0}}));
}

TEST(Report, DistractorIsABoxOverNoVisiblePixelOfItsClass) {
  const std::vector<MaskImage> masks = {RectMask(100, 80, 10, 10, 30, 30), RectMask(100, 80, 60, 50, 70, 60)};
  Detection d;
  d.x = 29, d.y = 29, d.w = 5, d.h = 5;  // covers pixel (29, 29) of the first instance
  EXPECT_FALSE(IsDistractor(d, masks));
  d.x = 30, d.y = 30;  // touches neither
  EXPECT_TRUE(IsDistractor(d, masks));
  d.x = 50, d.y = 45, d.w = 10.5, d.h = 6;  // reaches column 60 of the second after rounding out
  EXPECT_FALSE(IsDistractor(d, masks));
  EXPECT_TRUE(IsDistractor(d, {}));  // no instance of the class at all
}

TEST(Report, ObjectColoursDifferForTheYcbvObjects) {
  std::set<std::string> colours;
  for (int id = 1; id <= 19; ++id) colours.insert(CssColour(ObjectColour(id)));
  EXPECT_EQ(colours.size(), 19u);
  EXPECT_EQ(CssColour({255, 16, 0, 255}), "#ff1000");
}

void Write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

constexpr const char* kDetail = R"({
  "options": {"tau": 0.85},
  "objects": [{
    "scene_id": 1, "im_id": 2, "obj_id": 3, "boxes": 2,
    "R": [1, 0, 0, 0, 1, 0, 0, 0, 1], "t_mm": [10, 20, 900],
    "chosen_box": {"bbox": [5, 6, 70, 80], "score": 0.75, "index": 1},
    "iterations": 2, "best_weight": 0.6, "final_mean_weight": 0.5, "time_s": 0.02,
    "per_iteration": [{"mean_weight": 0.3, "best_weight": 0.5}, {"mean_weight": 0.5, "best_weight": 0.6}],
    "twins": {"ran": true, "candidates": 4},
    "refine": {"accepted": true, "rms_before_m": 0.003, "rms_after_m": 0.001}
  }]
})";

TEST(Report, ReadsTheEstimateDetail) {
  const fs::path dir = testing::TempDir("report_detail");
  Write(dir / "detail.json", kDetail);
  auto detail = ReadEstimateDetail((dir / "detail.json").string());
  ASSERT_TRUE(detail.ok()) << detail.status().ToString();
  EXPECT_DOUBLE_EQ(detail->tau, 0.85);
  ASSERT_EQ(detail->objects.size(), 1u);
  const ObjectDetail& d = detail->objects[0];
  EXPECT_EQ(d.key, (FrameKey{1, 2}));
  EXPECT_EQ(d.obj_id, 3);
  EXPECT_EQ(d.boxes, 2);
  EXPECT_TRUE(d.T_cam_obj.t.isApprox(Eigen::Vector3d(0.01, 0.02, 0.9)));
  EXPECT_EQ(d.chosen_box.obj_id, 3);
  EXPECT_DOUBLE_EQ(d.chosen_box.x, 5);
  EXPECT_DOUBLE_EQ(d.chosen_box.h, 80);
  EXPECT_DOUBLE_EQ(d.chosen_box.score, 0.75);
  ASSERT_EQ(d.per_iteration.size(), 2u);
  EXPECT_DOUBLE_EQ(d.per_iteration[1].mean_weight, 0.5);
  EXPECT_DOUBLE_EQ(d.per_iteration[1].best_weight, 0.6);
  EXPECT_TRUE(d.twins_ran);
  EXPECT_EQ(d.twin_candidates, 4);
  EXPECT_TRUE(d.refine_accepted);
  EXPECT_DOUBLE_EQ(d.refine_rms_after_mm, 1);
}

TEST(Report, DetailErrorsNameTheFileTheEntryAndTheField) {
  const fs::path dir = testing::TempDir("report_detail_errors");
  const std::string path = (dir / "detail.json").string();
  std::string broken = kDetail;
  broken.replace(broken.find("\"chosen_box\""), 12, "\"chosen\"");
  Write(path, broken);
  auto detail = ReadEstimateDetail(path);
  ASSERT_FALSE(detail.ok());
  EXPECT_EQ(detail.status().message(), path + ": objects[0]: chosen_box is missing");

  broken = kDetail;
  broken.replace(broken.find("\"mean_weight\": 0.5"), 18, "\"mean_weight\": \"x\"");
  Write(path, broken);
  detail = ReadEstimateDetail(path);
  ASSERT_FALSE(detail.ok());
  EXPECT_NE(detail.status().message().find("objects[0]: per_iteration[1] needs numbers"), std::string::npos)
      << detail.status().message();

  Write(path, "[1, 2]");
  detail = ReadEstimateDetail(path);
  ASSERT_FALSE(detail.ok());
  EXPECT_NE(detail.status().message().find(path + ": expected an object with a list 'objects'"), std::string::npos);
}

// A fake dataset with one instance of object 3 in frame (1, 2) and a result for it.
struct FakeRun {
  FakeDataset dataset{64, 48};
  ReportInput input;
  FakeRun() {
    const SE3 T(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.01, 0.02, 0.9));
    dataset.AddInstance(FrameKey{1, 2}, 3, T, RectMask(64, 48, 10, 10, 20, 20));
    dataset.SetEvalPoints(3, {Eigen::Vector3f(0.01f, 0, 0), Eigen::Vector3f(0, 0.01f, 0)});
    PoseResult r;
    r.scene_id = 1, r.im_id = 2, r.obj_id = 3, r.score = 0.6;
    r.T_cam_obj = T;
    input.results = {r};
    input.results_path = "results.csv";
  }
};

TEST(Report, RefusesToReplaceAFolderThatIsNotAReport) {
  FakeRun run;
  const fs::path dir = testing::TempDir("report_out_folder");
  Write(dir / "notes.txt", "mine");
  auto summary = WriteReport(run.dataset, run.input, dir.string());
  ASSERT_FALSE(summary.ok());
  EXPECT_NE(summary.status().message().find("is not a report of mcpose"), std::string::npos)
      << summary.status().message();
  EXPECT_TRUE(fs::exists(dir / "notes.txt"));
  EXPECT_TRUE(testing::LeftBeside(dir).empty());

  summary = WriteReport(run.dataset, run.input, (dir / "missing/report").string());
  ASSERT_FALSE(summary.ok());
  EXPECT_NE(summary.status().message().find("does not exist"), std::string::npos);
}

TEST(Report, RefusesDetailOfAnotherRunAndWritesNothing) {
  FakeRun run;
  EstimateDetail detail;
  ObjectDetail d;
  d.key = FrameKey{1, 2};
  d.obj_id = 3;
  d.T_cam_obj = run.input.results[0].T_cam_obj;
  d.T_cam_obj.t.z() += 0.001;  // a millimetre away: another pose
  detail.objects = {d};
  run.input.detail = detail;
  run.input.detail_path = "detail.json";
  const fs::path out = testing::TempDir("report_other_run") / "report";
  auto summary = WriteReport(run.dataset, run.input, out.string());
  ASSERT_FALSE(summary.ok());
  EXPECT_EQ(summary.status().message(),
            "detail.json: objects[0] (scene_id 1, im_id 2, obj_id 3) has another pose than results.csv: not the "
            "run that wrote the results");
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(testing::LeftBeside(out).empty());
}

TEST(Report, RefusesResultsAndBoxesOfAnImageOrClassTheDatasetLacks) {
  FakeRun run;
  run.input.results[0].im_id = 7;
  const fs::path out = testing::TempDir("report_unknown_image") / "report";
  auto summary = WriteReport(run.dataset, run.input, out.string());
  ASSERT_FALSE(summary.ok());
  EXPECT_EQ(summary.status().message(),
            "results.csv: a row of scene_id 1, im_id 7: the dataset fake_root has no such image");
  EXPECT_FALSE(fs::exists(out));

  run.input.results[0].im_id = 2;
  run.input.results[0].obj_id = 4;
  summary = WriteReport(run.dataset, run.input, out.string());
  ASSERT_FALSE(summary.ok());
  EXPECT_EQ(summary.status().message(),
            "results.csv: a row of scene_id 1, im_id 2: obj_id 4 is not a class of the dataset fake_root");
  EXPECT_FALSE(fs::exists(out));

  run.input.results[0].obj_id = 3;
  Detection box;
  box.scene_id = 1, box.image_id = 3, box.obj_id = 3;
  run.input.detections = std::vector<Detection>{box};
  run.input.detections_path = "dets.json";
  summary = WriteReport(run.dataset, run.input, out.string());
  ASSERT_FALSE(summary.ok());
  EXPECT_EQ(summary.status().message(), "dets.json: detection 0 (scene_id 1, image_id 3): no such image in fake_root");
  EXPECT_FALSE(fs::exists(out));

  box.image_id = 2, box.obj_id = 4;
  run.input.detections = std::vector<Detection>{box};
  summary = WriteReport(run.dataset, run.input, out.string());
  ASSERT_FALSE(summary.ok());
  EXPECT_EQ(summary.status().message(), "dets.json: detection 0 (scene_id 1, image_id 2): unknown class "
                                        "(category_id 4); the dataset has no model for it");

  // A box wholly outside the image.
  box.obj_id = 3, box.score = 0.5, box.x = 5000, box.y = 10, box.w = 20, box.h = 20;
  run.input.detections = std::vector<Detection>{box};
  summary = WriteReport(run.dataset, run.input, out.string());
  ASSERT_FALSE(summary.ok());
  EXPECT_NE(summary.status().message().find("dets.json: obj_id 3 in scene_id 1, image_id 2: box"), std::string::npos)
      << summary.status().message();
  EXPECT_NE(summary.status().message().find("lies outside"), std::string::npos) << summary.status().message();
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(testing::LeftBeside(out).empty());
}

// Two reports into one folder at once: the second is refused while the first holds the lock,
// and the lock file goes with the run that held it. (The report of a real dataset under the
// same lock: ReportReal in tests/.)
TEST(Report, OneRunAtATimeIntoAFolder) {
  FakeRun run;
  const fs::path out = testing::TempDir("report_lock") / "report";
  {
    auto held = io::FileLock::Acquire(out.string() + ".lock");
    ASSERT_TRUE(held.ok()) << held.status().ToString();
    auto summary = WriteReport(run.dataset, run.input, out.string());
    ASSERT_FALSE(summary.ok());
    EXPECT_EQ(summary.status().message(), out.string() + ".lock: held by another run writing the same output");
    EXPECT_FALSE(fs::exists(out));
  }
  EXPECT_FALSE(fs::exists(out.string() + ".lock"));
  // A file of the user's under the lock's name is refused and left as it was.
  Write(fs::path(out.string() + ".lock"), "mine");
  auto theirs = WriteReport(run.dataset, run.input, out.string());
  ASSERT_FALSE(theirs.ok());
  EXPECT_EQ(theirs.status().message(),
            out.string() + ".lock: exists and is not a lock file of mcpose; it is left alone (move it away)");
  std::ifstream kept(out.string() + ".lock");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(kept), {}), "mine");
  fs::remove(out.string() + ".lock");
  // One a killed run left (the lock file's text, no lock held) is taken over and removed.
  Write(fs::path(out.string() + ".lock"), "mcpose lock\n");
  // Free again: the run gets past the lock (to the fake dataset's missing meshes), and its own
  // lock file goes with it.
  auto summary = WriteReport(run.dataset, run.input, out.string());
  ASSERT_FALSE(summary.ok());
  EXPECT_EQ(summary.status().message(), "fake: no meshes");
  EXPECT_TRUE(testing::LeftBeside(out).empty());
}

}  // namespace
}  // namespace mcpose::report

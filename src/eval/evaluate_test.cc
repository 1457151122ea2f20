#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "eval/fake_dataset_test_util.h"
#include "mcpose/eval.h"
#include "test_data.h"

namespace mcpose {
namespace {

using eval_testing::FakeDataset;
using eval_testing::RectMask;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kBox = 2;     // an asymmetric object: random points in a box
constexpr int kBowl = 13;   // in the YCB-Video symmetric set: points on a circle
constexpr int kHidden = 5;  // listed in the ground truth but with no visible pixel

const FrameKey kF11{1, 1}, kF12{1, 2}, kF21{2, 1};

SE3 Pose(double angle_z, const Eigen::Vector3d& t) {
  return SE3(Eigen::AngleAxisd(angle_z, Eigen::Vector3d::UnitZ()).toRotationMatrix(), t);
}

PoseResult Row(const FrameKey& key, int obj_id, double score, const SE3& T) {
  PoseResult r;
  r.scene_id = key.scene_id;
  r.im_id = key.image_id;
  r.obj_id = obj_id;
  r.score = score;
  r.T_cam_obj = T;
  return r;
}

const InstanceEval* Find(const EvalReport& report, const FrameKey& key, int obj_id) {
  for (const auto& e : report.instances) {
    if (e.key == key && e.obj_id == obj_id) return &e;
  }
  return nullptr;
}

// Three frames: (1,1) box + bowl + hidden object, (1,2) box, (2,1) bowl.
class EvalFakeTest : public ::testing::Test {
 protected:
  EvalFakeTest() : ds_(32, 24) {
    std::mt19937 gen(7);
    std::uniform_real_distribution<float> u(-0.04f, 0.04f);
    std::vector<Eigen::Vector3f> box;
    for (int i = 0; i < 300; ++i) box.emplace_back(u(gen), 0.5f * u(gen), 0.25f * u(gen));
    std::vector<Eigen::Vector3f> circle;
    for (int k = 0; k < 72; ++k) {
      const double a = 2.0 * M_PI * k / 72;
      circle.emplace_back(static_cast<float>(0.06 * std::cos(a)),
                          static_cast<float>(0.06 * std::sin(a)), 0.0f);
    }
    ds_.SetEvalPoints(kBox, box);
    ds_.SetEvalPoints(kBowl, circle);
    ds_.SetEvalPoints(kHidden, box);

    ds_.AddInstance(kF11, kBox, T_box_, RectMask(32, 24, 2, 2, 8, 6));
    ds_.AddInstance(kF11, kBowl, T_bowl_, RectMask(32, 24, 10, 10, 20, 20));
    ds_.AddInstance(kF11, kHidden, T_box_, RectMask(32, 24, 0, 0, 0, 0));
    ds_.AddInstance(kF12, kBox, T_box_, RectMask(32, 24, 30, 22, 31, 23));  // one pixel
    ds_.AddInstance(kF21, kBowl, T_bowl_, RectMask(32, 24, 0, 0, 32, 24));
  }

  // Results: in (1,1) the box has a 1 cm-off row with the higher score and an exact row with a
  // lower one; the bowl is rotated by 5 point spacings about its axis; the hidden object has a
  // row. (1,2) has no row; (2,1) is exact.
  std::vector<PoseResult> Results() const {
    return {
        Row(kF11, kBox, 0.4, T_box_),
        Row(kF11, kBox, 0.9, SE3(T_box_.R, T_box_.t + Eigen::Vector3d(0.01, 0, 0))),
        Row(kF11, kBowl, 0.8, SE3(T_bowl_.R * Pose(2.0 * M_PI * 5 / 72, {0, 0, 0}).R, T_bowl_.t)),
        Row(kF11, kHidden, 0.8, T_box_),
        Row(kF21, kBowl, 0.5, T_bowl_),
        Row(FrameKey{7, 7}, kBox, 1.0, T_box_),  // a frame the dataset does not have
    };
  }

  FakeDataset ds_;
  SE3 T_box_ = Pose(0.3, {0.05, -0.02, 0.8});
  SE3 T_bowl_ = Pose(-1.1, {-0.1, 0.03, 0.9});
};

TEST_F(EvalFakeTest, TargetsAreVisibleInstancesOnly) {
  auto report = Evaluate(ds_, Results(), nullptr, EvalOptions());
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  ASSERT_EQ(report->instances.size(), 4u);
  EXPECT_EQ(Find(*report, kF11, kHidden), nullptr);
  const InstanceEval* one_pixel = Find(*report, kF12, kBox);
  ASSERT_NE(one_pixel, nullptr);
  EXPECT_EQ(one_pixel->visible_pixels, 1);
  EXPECT_EQ(Find(*report, kF11, kBowl)->visible_pixels, 100);
  EXPECT_EQ(Find(*report, kF11, kBowl)->gt_index, 1);
  ASSERT_EQ(report->per_object.size(), 2u);
  EXPECT_EQ(report->per_object[0].obj_id, kBox);
  EXPECT_EQ(report->per_object[0].name, "fake_2");
  EXPECT_EQ(report->per_object[1].obj_id, kBowl);
  EXPECT_EQ(report->overall.obj_id, 0);
  EXPECT_EQ(report->overall.name, "ALL");
  EXPECT_EQ(report->overall.instances, 4);
  EXPECT_EQ(report->overall.with_result, 3);
  EXPECT_EQ(report->unmatched_rows, 2);  // the hidden object's row and frame 7/7's
}

TEST_F(EvalFakeTest, MissingResultIsAFailure) {
  auto report = Evaluate(ds_, Results(), nullptr, EvalOptions());
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  const InstanceEval* missing = Find(*report, kF12, kBox);
  ASSERT_NE(missing, nullptr);
  EXPECT_FALSE(missing->has_result);
  EXPECT_EQ(missing->add_m, kInf);
  EXPECT_EQ(missing->adds_m, kInf);
  EXPECT_EQ(missing->add_or_adds_m, kInf);
  const AccuracySummary& box = report->per_object[0];
  EXPECT_EQ(box.instances, 2);
  EXPECT_EQ(box.with_result, 1);
  EXPECT_DOUBLE_EQ(box.add_lt_2cm, 0.5);
  EXPECT_DOUBLE_EQ(box.add_s_lt_4cm, 0.5);
  EXPECT_NEAR(box.add_auc, (0.1 - 0.01) / (2 * 0.1), 1e-9);
}

TEST_F(EvalFakeTest, HighestScoreRowIsUsed) {
  auto report = Evaluate(ds_, Results(), nullptr, EvalOptions());
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  const InstanceEval* e = Find(*report, kF11, kBox);
  ASSERT_NE(e, nullptr);
  EXPECT_TRUE(e->has_result);
  EXPECT_NEAR(e->add_m, 0.01, 1e-9);  // the 0.9 row, not the exact 0.4 row
  EXPECT_EQ(e->result_index, 1);
  EXPECT_NEAR(e->add_or_adds_m, 0.01, 1e-9);
  EXPECT_LE(e->adds_m, e->add_m + 1e-12);
}

TEST_F(EvalFakeTest, SymmetricIdsUseAddS) {
  auto report = Evaluate(ds_, Results(), nullptr, EvalOptions());
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  const InstanceEval* bowl = Find(*report, kF11, kBowl);
  ASSERT_NE(bowl, nullptr);
  EXPECT_LT(bowl->adds_m, 1e-6);
  EXPECT_GT(bowl->add_m, 0.02);  // chord of 25 degrees on a 6 cm circle: 2.6 cm
  EXPECT_EQ(bowl->add_or_adds_m, bowl->adds_m);

  // Overall: box 1 cm, bowl ~0 (ADD-S) / 2.6 cm (ADD), box missing, bowl exact.
  const AccuracySummary& all = report->overall;
  EXPECT_DOUBLE_EQ(all.add_s_lt_2cm, 0.75);
  EXPECT_DOUBLE_EQ(all.add_lt_2cm, 0.5);
  EXPECT_DOUBLE_EQ(all.add_lt_4cm, 0.75);
  EXPECT_DOUBLE_EQ(all.adds_lt_2cm, 0.75);
  EXPECT_NEAR(all.add_s_auc, (0.09 + 0.1 + 0.0 + 0.1) / 0.4, 1e-5);
  EXPECT_NEAR(all.add_auc, (0.09 + (0.1 - bowl->add_m) + 0.0 + 0.1) / 0.4, 1e-9);

  // With no symmetric ids, ADD(-S) is ADD.
  EvalOptions no_sym;
  no_sym.symmetric_obj_ids.clear();
  auto plain = Evaluate(ds_, Results(), nullptr, no_sym);
  ASSERT_TRUE(plain.ok());
  EXPECT_EQ(Find(*plain, kF11, kBowl)->add_or_adds_m, bowl->add_m);
  EXPECT_DOUBLE_EQ(plain->overall.add_s_lt_2cm, 0.5);

  // With the box declared symmetric, its ADD(-S) is its ADD-S.
  EvalOptions box_sym;
  box_sym.symmetric_obj_ids = {kBox};
  auto boxed = Evaluate(ds_, Results(), nullptr, box_sym);
  ASSERT_TRUE(boxed.ok());
  const InstanceEval* box = Find(*boxed, kF11, kBox);
  EXPECT_EQ(box->add_or_adds_m, box->adds_m);
  EXPECT_EQ(Find(*boxed, kF11, kBowl)->add_or_adds_m, bowl->add_m);
}

TEST_F(EvalFakeTest, AucMaxOption) {
  EvalOptions options;
  options.auc_max_m = 0.02;
  auto report = Evaluate(ds_, Results(), nullptr, options);
  ASSERT_TRUE(report.ok());
  EXPECT_NEAR(report->per_object[0].add_auc, (0.02 - 0.01) / (2 * 0.02), 1e-9);
  options.auc_max_m = 0;
  EXPECT_EQ(Evaluate(ds_, Results(), nullptr, options).status().code(),
            StatusCode::kInvalidArgument);
}

TEST_F(EvalFakeTest, DetectionsLimitTheFrames) {
  Detection d12, d21, d99;
  d12.scene_id = 1, d12.image_id = 2, d12.obj_id = 9;  // any class selects the frame
  d21.scene_id = 2, d21.image_id = 1, d21.obj_id = kBowl;
  d99.scene_id = 9, d99.image_id = 9, d99.obj_id = kBox;  // not in the dataset: ignored
  const std::vector<Detection> detections = {d12, d21, d21, d99};
  auto report = Evaluate(ds_, Results(), &detections, EvalOptions());
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  ASSERT_EQ(report->instances.size(), 2u);
  EXPECT_NE(Find(*report, kF12, kBox), nullptr);
  EXPECT_NE(Find(*report, kF21, kBowl), nullptr);
  EXPECT_EQ(report->overall.with_result, 1);
  EXPECT_EQ(report->unmatched_rows, 5);  // frame 1/1's four rows and frame 7/7's

  const std::vector<Detection> none;
  auto empty = Evaluate(ds_, Results(), &none, EvalOptions());
  ASSERT_TRUE(empty.ok());
  EXPECT_TRUE(empty->instances.empty());
  EXPECT_TRUE(empty->per_object.empty());
  EXPECT_EQ(empty->overall.instances, 0);
  EXPECT_EQ(empty->overall.add_auc, 0.0);
}

TEST_F(EvalFakeTest, EvalPointsAreLoadedOncePerObject) {
  auto report = Evaluate(ds_, Results(), nullptr, EvalOptions());
  ASSERT_TRUE(report.ok());
  EXPECT_EQ(ds_.eval_point_loads, 2);  // box and bowl; the hidden object is not a target
}

TEST_F(EvalFakeTest, DatasetErrorsPropagate) {
  ds_.eval_points_error = DataLoss("points.xyz is truncated");
  auto report = Evaluate(ds_, Results(), nullptr, EvalOptions());
  ASSERT_FALSE(report.ok());
  EXPECT_EQ(report.status().code(), StatusCode::kDataLoss);
  EXPECT_EQ(report.status().message(), "points.xyz is truncated");

  ds_.eval_points_error = Status::Ok();
  ds_.visible_mask_error = NotFound("mask_visib/000000_000000.png");
  report = Evaluate(ds_, Results(), nullptr, EvalOptions());
  ASSERT_FALSE(report.ok());
  EXPECT_EQ(report.status().code(), StatusCode::kNotFound);
}

TEST_F(EvalFakeTest, EmptyEvalPointsAreAnError) {
  ds_.SetEvalPoints(kBox, {});
  auto report = Evaluate(ds_, Results(), nullptr, EvalOptions());
  ASSERT_FALSE(report.ok());
  EXPECT_EQ(report.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(report.status().message().find("obj_id 2"), std::string::npos);
}

TEST_F(EvalFakeTest, NanPoseIsAFailure) {
  std::vector<PoseResult> results = Results();
  results[1].T_cam_obj.t.x() = std::nan("");
  auto report = Evaluate(ds_, results, nullptr, EvalOptions());
  ASSERT_TRUE(report.ok());
  const InstanceEval* e = Find(*report, kF11, kBox);
  EXPECT_TRUE(e->has_result);
  EXPECT_EQ(e->add_m, kInf);
  EXPECT_EQ(e->adds_m, kInf);
  EXPECT_DOUBLE_EQ(report->per_object[0].add_s_lt_4cm, 0.0);
}

// ---- Real data: YCB-Video (needs the src/io readers) ---------------------------------------

std::vector<PoseResult> GroundTruthResults(const Dataset& ds) {
  std::vector<PoseResult> results;
  for (const FrameKey& key : ds.Frames()) {
    auto frame = ds.LoadFrame(key);
    EXPECT_TRUE(frame.ok()) << frame.status().ToString();
    if (!frame.ok()) continue;
    for (const GtInstance& gt : frame->gt) results.push_back(Row(key, gt.obj_id, 1.0, gt.T_cam_obj));
  }
  return results;
}

TEST(EvalYcbv, GroundTruthAgainstItselfIsPerfect) {
  auto ds = Dataset::Open(testing::YcbvDir());
  ASSERT_TRUE(ds.ok()) << ds.status().ToString();
  const std::vector<PoseResult> results = GroundTruthResults(**ds);
  ASSERT_FALSE(results.empty());
  auto report = Evaluate(**ds, results, nullptr, EvalOptions());
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  ASSERT_GT(report->overall.instances, 0);
  for (const InstanceEval& e : report->instances) {
    EXPECT_TRUE(e.has_result);
    EXPECT_EQ(e.add_m, 0.0);
    EXPECT_EQ(e.adds_m, 0.0);
    EXPECT_GT(e.visible_pixels, 0);
  }
  const AccuracySummary& all = report->overall;
  EXPECT_EQ(all.with_result, all.instances);
  EXPECT_EQ(all.add_lt_2cm, 1.0);
  EXPECT_EQ(all.add_s_lt_2cm, 1.0);
  EXPECT_EQ(all.adds_lt_2cm, 1.0);
  EXPECT_DOUBLE_EQ(all.add_auc, 1.0);
  EXPECT_DOUBLE_EQ(all.add_s_auc, 1.0);
  int per_object_total = 0;
  for (const AccuracySummary& s : report->per_object) {
    per_object_total += s.instances;
    EXPECT_EQ(s.name, (*ds)->ObjectName(s.obj_id));
    EXPECT_EQ(s.add_lt_2cm, 1.0);
  }
  EXPECT_EQ(per_object_total, all.instances);
  for (size_t i = 1; i < report->per_object.size(); ++i) {
    EXPECT_LT(report->per_object[i - 1].obj_id, report->per_object[i].obj_id);
  }
}

TEST(EvalYcbv, InvisibleMugIsNotATarget) {
  auto ds = Dataset::Open(testing::YcbvDir());
  ASSERT_TRUE(ds.ok()) << ds.status().ToString();
  const FrameKey key{3, 138};
  auto frame = (*ds)->LoadFrame(key);
  ASSERT_TRUE(frame.ok()) << frame.status().ToString();
  std::set<int> listed;
  for (const GtInstance& gt : frame->gt) listed.insert(gt.obj_id);
  EXPECT_EQ(listed, (std::set<int>{4, 8, 14, 20}));

  Detection d;
  d.scene_id = key.scene_id;
  d.image_id = key.image_id;
  d.obj_id = 14;
  const std::vector<Detection> detections = {d};
  std::vector<PoseResult> results;
  for (const GtInstance& gt : frame->gt) results.push_back(Row(key, gt.obj_id, 1.0, gt.T_cam_obj));
  auto report = Evaluate(**ds, results, &detections, EvalOptions());
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  std::set<int> targets;
  for (const InstanceEval& e : report->instances) {
    EXPECT_EQ(e.key, key);
    targets.insert(e.obj_id);
  }
  EXPECT_EQ(targets, (std::set<int>{4, 8, 20}));
  EXPECT_EQ(report->overall.instances, 3);
}

// Several instances of one class in a frame: the rows in order of score each take the nearest
// instance still without one; an instance left over has no result.
TEST(EvalInstances, RowsTakeTheNearestInstanceInScoreOrder) {
  FakeDataset ds(32, 24);
  std::vector<Eigen::Vector3f> points;
  for (int i = 0; i < 8; ++i) points.emplace_back(0.01f * (i % 2), 0.02f * (i / 2 % 2), 0.03f * (i / 4));
  ds.SetEvalPoints(kBox, points);
  const FrameKey key{3, 4};
  const SE3 a = Pose(0, {0, 0, 1}), b = Pose(0, {0.2, 0, 1}), c = Pose(0, {0.4, 0, 1});
  ds.AddInstance(key, kBox, a, RectMask(32, 24, 0, 0, 4, 4));
  ds.AddInstance(key, kBox, b, RectMask(32, 24, 10, 0, 14, 4));
  ds.AddInstance(key, kBox, c, RectMask(32, 24, 20, 0, 24, 4));
  const auto shifted = [](const SE3& T, double dx) { return SE3(T.R, T.t + Eigen::Vector3d(dx, 0, 0)); };
  // Rows near b (the best), near a, and a second one near b: c is left without a row.
  const std::vector<PoseResult> rows = {Row(key, kBox, 0.5, shifted(a, 0.003)), Row(key, kBox, 0.9, shifted(b, 0.001)),
                                        Row(key, kBox, 0.4, shifted(b, 0.005))};
  auto report = Evaluate(ds, rows, nullptr, EvalOptions());
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  ASSERT_EQ(report->instances.size(), 3u);
  EXPECT_NEAR(report->instances[0].add_m, 0.003, 1e-9);
  EXPECT_NEAR(report->instances[1].add_m, 0.001, 1e-9);
  EXPECT_EQ(report->instances[0].result_index, 0);
  EXPECT_EQ(report->instances[1].result_index, 1);
  EXPECT_EQ(report->instances[2].result_index, 2);
  EXPECT_TRUE(report->instances[2].has_result);  // the last row goes to the one left: c
  EXPECT_NEAR(report->instances[2].add_m, 0.195, 1e-9);
  // Two rows for three instances: the third has none.
  auto two = Evaluate(ds, {rows[0], rows[1]}, nullptr, EvalOptions());
  ASSERT_TRUE(two.ok());
  EXPECT_TRUE(two->instances[0].has_result);
  EXPECT_TRUE(two->instances[1].has_result);
  EXPECT_FALSE(two->instances[2].has_result);
  EXPECT_EQ(two->instances[2].result_index, -1);
  EXPECT_EQ(two->overall.with_result, 2);
}

}  // namespace
}  // namespace mcpose

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "eval/fake_dataset_test_util.h"
#include "mcpose/eval.h"
#include "test_data.h"

namespace mcpose {
namespace {

using eval_testing::FakeDataset;
using eval_testing::RectMask;

constexpr int kW = 64, kH = 48;

bool SameDetections(const std::vector<Detection>& a, const std::vector<Detection>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    const auto tie = [](const Detection& d) {
      return std::tie(d.scene_id, d.image_id, d.obj_id, d.score, d.x, d.y, d.w, d.h, d.time_s);
    };
    if (tie(a[i]) != tie(b[i])) return false;
  }
  return true;
}

void ExpectInsideImage(const Detection& d, int width, int height) {
  EXPECT_GE(d.x, 0.0);
  EXPECT_GE(d.y, 0.0);
  EXPECT_GE(d.w, 1.0);
  EXPECT_GE(d.h, 1.0);
  EXPECT_LE(d.x + d.w, width + 1e-9);
  EXPECT_LE(d.y + d.h, height + 1e-9);
}

// Frame (1, 1): three rectangles (one touching the corner), one irregular mask, one empty mask.
FakeDataset SmallDataset() {
  FakeDataset ds(kW, kH);
  ds.AddInstance({1, 1}, 3, SE3(), RectMask(kW, kH, 5, 7, 15, 20));
  ds.AddInstance({1, 1}, 1, SE3(), RectMask(kW, kH, 0, 0, 4, 3));
  MaskImage irregular = RectMask(kW, kH, 0, 0, 0, 0);
  irregular.values[10 * kW + 40] = 1;
  irregular.values[30 * kW + 33] = 255;
  irregular.values[22 * kW + 50] = 1;
  ds.AddInstance({1, 1}, 7, SE3(), irregular);
  ds.AddInstance({1, 1}, 8, SE3(), RectMask(kW, kH, 0, 0, 0, 0));
  ds.AddInstance({2, 5}, 3, SE3(), RectMask(kW, kH, 50, 40, 64, 48));
  return ds;
}

// One instance per (frame, obj_id) with a known tight box: n_frames x 20 instances.
FakeDataset ManyInstances(int n_frames) {
  FakeDataset ds(kW, kH);
  for (int f = 0; f < n_frames; ++f) {
    for (int obj = 1; obj <= 20; ++obj) {
      const int x0 = (f * 7 + obj * 3) % (kW - 12), y0 = (f * 5 + obj) % (kH - 10);
      ds.AddInstance({f / 10 + 1, f % 10 + 1}, obj, SE3(),
                     RectMask(kW, kH, x0, y0, x0 + 4 + obj % 8, y0 + 2 + f % 8));
    }
  }
  return ds;
}

TEST(GtDetections, ZeroJitterGivesTheTightMaskBox) {
  const FakeDataset ds = SmallDataset();
  GtDetectionOptions options;
  options.jitter = 0;
  options.distractors = 0;
  auto dets = DetectionsFromGroundTruth(ds, options);
  ASSERT_TRUE(dets.ok()) << dets.status().ToString();
  ASSERT_EQ(dets->size(), 4u);  // the empty mask gives no box
  // Sorted by (scene, image, obj_id).
  const Detection& a = (*dets)[0];
  EXPECT_EQ(std::tie(a.scene_id, a.image_id, a.obj_id), std::make_tuple(1, 1, 1));
  EXPECT_EQ(std::make_tuple(a.x, a.y, a.w, a.h), std::make_tuple(0.0, 0.0, 4.0, 3.0));
  const Detection& b = (*dets)[1];
  EXPECT_EQ(b.obj_id, 3);
  EXPECT_EQ(std::make_tuple(b.x, b.y, b.w, b.h), std::make_tuple(5.0, 7.0, 10.0, 13.0));
  const Detection& c = (*dets)[2];
  EXPECT_EQ(c.obj_id, 7);
  EXPECT_EQ(std::make_tuple(c.x, c.y, c.w, c.h), std::make_tuple(33.0, 10.0, 18.0, 21.0));
  const Detection& d = (*dets)[3];
  EXPECT_EQ(std::tie(d.scene_id, d.image_id, d.obj_id), std::make_tuple(2, 5, 3));
  EXPECT_EQ(std::make_tuple(d.x, d.y, d.w, d.h), std::make_tuple(50.0, 40.0, 14.0, 8.0));
  for (const Detection& det : *dets) {
    EXPECT_GE(det.score, 0.5);
    EXPECT_LT(det.score, 1.0);
    EXPECT_EQ(det.time_s, -1.0);
  }
}

TEST(GtDetections, BoxesStayInsideTheImage) {
  const FakeDataset ds = ManyInstances(20);
  for (double jitter : {0.1, 0.5, 2.0}) {
    GtDetectionOptions options;
    options.jitter = jitter;
    options.distractors = 0.5;
    options.seed = 11;
    auto dets = DetectionsFromGroundTruth(ds, options);
    ASSERT_TRUE(dets.ok()) << dets.status().ToString();
    ASSERT_GE(dets->size(), 400u);
    for (const Detection& d : *dets) ExpectInsideImage(d, kW, kH);
  }
  const FakeDataset small = SmallDataset();
  GtDetectionOptions options;
  options.jitter = 0.5;
  options.distractors = 1.0;
  auto dets = DetectionsFromGroundTruth(small, options);
  ASSERT_TRUE(dets.ok());
  EXPECT_EQ(dets->size(), 8u);
  for (const Detection& d : *dets) ExpectInsideImage(d, kW, kH);
}

TEST(GtDetections, JitterMovesEachSideByAtMostItsShare) {
  const FakeDataset ds = ManyInstances(10);
  GtDetectionOptions options;
  options.jitter = 0.1;
  options.distractors = 0;
  options.seed = 3;
  auto jittered = DetectionsFromGroundTruth(ds, options);
  options.jitter = 0;
  auto tight = DetectionsFromGroundTruth(ds, options);
  ASSERT_TRUE(jittered.ok() && tight.ok());
  ASSERT_EQ(jittered->size(), tight->size());
  int moved = 0;
  for (size_t i = 0; i < tight->size(); ++i) {
    const Detection& t = (*tight)[i];
    const Detection& j = (*jittered)[i];
    ASSERT_EQ(std::tie(t.scene_id, t.image_id, t.obj_id), std::tie(j.scene_id, j.image_id, j.obj_id));
    EXPECT_LE(std::abs(j.x - t.x), 0.1 * t.w + 1e-9);
    EXPECT_LE(std::abs((j.x + j.w) - (t.x + t.w)), 0.1 * t.w + 1e-9);
    EXPECT_LE(std::abs(j.y - t.y), 0.1 * t.h + 1e-9);
    EXPECT_LE(std::abs((j.y + j.h) - (t.y + t.h)), 0.1 * t.h + 1e-9);
    moved += (j.x != t.x) + (j.y != t.y) + (j.w != t.w) + (j.h != t.h);
  }
  EXPECT_GT(moved, static_cast<int>(tight->size()));  // jitter does move boxes
}

TEST(GtDetections, DeterministicForASeed) {
  const FakeDataset ds = ManyInstances(10);
  GtDetectionOptions options;
  options.seed = 42;
  auto a = DetectionsFromGroundTruth(ds, options);
  auto b = DetectionsFromGroundTruth(ds, options);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_TRUE(SameDetections(*a, *b));
  options.seed = 43;
  auto c = DetectionsFromGroundTruth(ds, options);
  ASSERT_TRUE(c.ok());
  EXPECT_FALSE(SameDetections(*a, *c));
}

TEST(GtDetections, InstanceBoxesDoNotDependOnOtherFrames) {
  FakeDataset both(kW, kH), only_second(kW, kH);
  both.AddInstance({1, 1}, 2, SE3(), RectMask(kW, kH, 3, 3, 20, 20));
  for (FakeDataset* ds : {&both, &only_second}) {
    ds->AddInstance({1, 2}, 5, SE3(), RectMask(kW, kH, 10, 12, 30, 40));
    ds->AddInstance({1, 2}, 6, SE3(), RectMask(kW, kH, 30, 2, 50, 20));
  }
  GtDetectionOptions options;
  options.distractors = 0.5;
  options.seed = 5;
  auto a = DetectionsFromGroundTruth(both, options);
  auto b = DetectionsFromGroundTruth(only_second, options);
  ASSERT_TRUE(a.ok() && b.ok());
  std::vector<Detection> a_second;
  for (const Detection& d : *a) {
    if (d.image_id == 2) a_second.push_back(d);
  }
  EXPECT_TRUE(SameDetections(a_second, *b));
}

TEST(GtDetections, DistractorRateAndScores) {
  const FakeDataset ds = ManyInstances(100);  // 2000 instances
  GtDetectionOptions options;
  options.jitter = 0;
  options.distractors = 0.3;
  options.seed = 9;
  auto dets = DetectionsFromGroundTruth(ds, options);
  ASSERT_TRUE(dets.ok()) << dets.status().ToString();
  auto tight_opts = options;
  tight_opts.distractors = 0;
  auto tight = DetectionsFromGroundTruth(ds, tight_opts);
  ASSERT_TRUE(tight.ok());
  ASSERT_EQ(tight->size(), 2000u);

  // Group by (scene, image, obj): the box at the tight position is the true one, the other the
  // distractor, which has the same size and lies anywhere inside the image.
  std::map<std::tuple<int, int, int>, Detection> truth;
  for (const Detection& t : *tight) truth[{t.scene_id, t.image_id, t.obj_id}] = t;
  int distractors = 0;
  for (const Detection& d : *dets) {
    const Detection& t = truth.at({d.scene_id, d.image_id, d.obj_id});
    ExpectInsideImage(d, kW, kH);
    EXPECT_EQ(d.w, t.w);
    EXPECT_EQ(d.h, t.h);
    if (d.x == t.x && d.y == t.y) {
      EXPECT_GE(d.score, 0.5);
      EXPECT_LT(d.score, 1.0);
      EXPECT_EQ(d.score, t.score);  // the same stream draws the same score
    } else {
      ++distractors;
      EXPECT_GE(d.score, 0.2);
      EXPECT_LT(d.score, 0.7);
    }
  }
  EXPECT_EQ(static_cast<int>(dets->size()) - 2000, distractors);
  EXPECT_NEAR(distractors / 2000.0, 0.3, 0.04);

  options.distractors = 0;
  EXPECT_EQ(DetectionsFromGroundTruth(ds, options)->size(), 2000u);
  options.distractors = 1;
  EXPECT_EQ(DetectionsFromGroundTruth(ds, options)->size(), 4000u);
}

TEST(GtDetections, SortedBySceneImageObjectAndScore) {
  const FakeDataset ds = ManyInstances(30);
  GtDetectionOptions options;
  options.distractors = 0.7;
  auto dets = DetectionsFromGroundTruth(ds, options);
  ASSERT_TRUE(dets.ok());
  for (size_t i = 1; i < dets->size(); ++i) {
    const Detection& p = (*dets)[i - 1];
    const Detection& q = (*dets)[i];
    const auto pk = std::make_tuple(p.scene_id, p.image_id, p.obj_id, -p.score);
    const auto qk = std::make_tuple(q.scene_id, q.image_id, q.obj_id, -q.score);
    EXPECT_LE(pk, qk) << "at " << i;
  }
}

TEST(GtDetections, MinVisiblePixels) {
  const FakeDataset ds = SmallDataset();  // masks of 130, 12, 3, 0 and 112 pixels
  GtDetectionOptions options;
  options.distractors = 0;
  options.min_visible_pixels = 12;
  auto dets = DetectionsFromGroundTruth(ds, options);
  ASSERT_TRUE(dets.ok());
  EXPECT_EQ(dets->size(), 3u);
  options.min_visible_pixels = 13;
  EXPECT_EQ(DetectionsFromGroundTruth(ds, options)->size(), 2u);
}

// A ground-truth class the dataset has no model for gets no box (and one warning).
TEST(GtDetections, NoBoxForAClassWithoutAModel) {
  FakeDataset ds = SmallDataset();
  ds.without_model = {3};
  GtDetectionOptions options;
  options.jitter = 0;
  options.distractors = 0;
  auto dets = DetectionsFromGroundTruth(ds, options);
  ASSERT_TRUE(dets.ok()) << dets.status().ToString();
  ASSERT_EQ(dets->size(), 2u);  // obj 1 and obj 7; obj 3's two instances left out
  for (const Detection& d : *dets) EXPECT_NE(d.obj_id, 3);
}

TEST(GtDetections, InvalidOptions) {
  const FakeDataset ds = SmallDataset();
  GtDetectionOptions bad;
  bad.jitter = -0.1;
  EXPECT_EQ(DetectionsFromGroundTruth(ds, bad).status().code(), StatusCode::kInvalidArgument);
  bad = GtDetectionOptions();
  bad.distractors = 1.5;
  EXPECT_EQ(DetectionsFromGroundTruth(ds, bad).status().code(), StatusCode::kInvalidArgument);
  bad = GtDetectionOptions();
  bad.distractors = std::nan("");
  EXPECT_EQ(DetectionsFromGroundTruth(ds, bad).status().code(), StatusCode::kInvalidArgument);
  bad = GtDetectionOptions();
  bad.min_visible_pixels = 0;
  EXPECT_EQ(DetectionsFromGroundTruth(ds, bad).status().code(), StatusCode::kInvalidArgument);
}

TEST(GtDetections, DatasetErrorsPropagate) {
  FakeDataset ds = SmallDataset();
  ds.visible_mask_error = DataLoss("label.png is truncated");
  auto dets = DetectionsFromGroundTruth(ds, GtDetectionOptions());
  ASSERT_FALSE(dets.ok());
  EXPECT_EQ(dets.status().code(), StatusCode::kDataLoss);
}

// ---- Real data: YCB-Video (needs the src/io readers) ---------------------------------------

TEST(GtDetectionsYcbv, TightBoxesOfVisibleInstances) {
  auto ds = Dataset::Open(testing::YcbvDir());
  ASSERT_TRUE(ds.ok()) << ds.status().ToString();
  GtDetectionOptions options;
  options.jitter = 0;
  options.distractors = 0;
  auto dets = DetectionsFromGroundTruth(**ds, options);
  ASSERT_TRUE(dets.ok()) << dets.status().ToString();
  ASSERT_FALSE(dets->empty());
  for (const Detection& d : *dets) ExpectInsideImage(d, 640, 480);

  // data/0003/000138: the mug (14) has no visible pixel, hence no box; the others have one.
  std::vector<int> in_frame;
  for (const Detection& d : *dets) {
    if (d.scene_id == 3 && d.image_id == 138) in_frame.push_back(d.obj_id);
  }
  EXPECT_EQ(in_frame, (std::vector<int>{4, 8, 20}));

  // One box per visible instance, the same count as Evaluate's targets.
  auto report = Evaluate(**ds, {}, nullptr, EvalOptions());
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_EQ(dets->size(), report->instances.size());
}

}  // namespace
}  // namespace mcpose

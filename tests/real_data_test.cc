// Integration tests on real YCB-Video frames (../shared/data/ycbv, see tests/test_data.h).
#include <algorithm>
#include <cmath>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "analysis/ambiguity_instance.h"
#include "mcpose/analysis/refine_floor.h"
#include "engine/box_scorer.h"
#include "engine/context.h"
#include "engine/initialize.h"
#include "mcpose/run.h"
#include "engine/refinement.h"
#include "mcpose/dataset.h"
#include "mcpose/eval.h"
#include "render/raster.h"
#include "test_data.h"

namespace mcpose {

// Readable test parameters ("scene 49 image 1"), found by gtest through ADL.
void PrintTo(const FrameKey& k, std::ostream* os) { *os << "scene " << k.scene_id << " image " << k.image_id; }

namespace {

std::unique_ptr<Dataset> OpenYcbv() {
  auto ds = Dataset::Open(testing::YcbvDir());
  EXPECT_TRUE(ds.ok()) << ds.status().ToString();
  return ds.ok() ? std::move(ds).value() : nullptr;
}

// Full-image z-buffer of one mesh at one pose, rendered by the scalar reference raster core.
std::vector<float> RenderFullImage(const Mesh& mesh, const SE3& T, const Intrinsics& K) {
  render::RasterParams p;
  p.fx = K.fx, p.fy = K.fy, p.cx = K.cx, p.cy = K.cy;
  p.box = render::PixelRect{0, 0, K.width, K.height};
  std::vector<render::ScreenVertex> sv(mesh.vertices_m.size());
  render::ProjectVertices(mesh.vertices_m, T.R.cast<float>(), T.t.cast<float>(), p, sv);
  std::vector<float> z(static_cast<size_t>(K.width) * K.height, INFINITY);
  render::RasterizeDepthReference(sv, mesh.triangles, p, z.data(), nullptr);
  return z;
}

// Renders every ground-truth object of a frame into one z-buffer (the nearest object owns a
// pixel) and compares each object's pixels with label.png (IoU) and, where both mark the
// object and the depth is valid, with the observed depth (median |dz|).
class GroundTruthRender : public ::testing::TestWithParam<FrameKey> {};

TEST_P(GroundTruthRender, ReproducesLabelMaskAndObservedDepth) {
  auto ds = OpenYcbv();
  ASSERT_TRUE(ds);
  auto frame = ds->LoadFrame(GetParam());
  ASSERT_TRUE(frame.ok()) << frame.status().ToString();
  const Intrinsics& K = frame->K;
  const size_t n = static_cast<size_t>(K.width) * K.height;
  std::vector<float> zmin(n, INFINITY);
  std::vector<int> owner(n, -1);
  for (size_t g = 0; g < frame->gt.size(); ++g) {
    auto mesh = ds->LoadMesh(frame->gt[g].obj_id);
    ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
    const std::vector<float> z = RenderFullImage(*mesh, frame->gt[g].T_cam_obj, K);
    for (size_t i = 0; i < n; ++i)
      if (z[i] < zmin[i]) zmin[i] = z[i], owner[i] = static_cast<int>(g);
  }
  for (size_t g = 0; g < frame->gt.size(); ++g) {
    auto mask = ds->LoadVisibleMask(frame->key, frame->gt[g]);
    ASSERT_TRUE(mask.ok()) << mask.status().ToString();
    int inter = 0, uni = 0;
    std::vector<float> dz, dz_signed;
    for (size_t i = 0; i < n; ++i) {
      const bool r = owner[i] == static_cast<int>(g), m = mask->values[i] != 0;
      inter += r && m;
      uni += r || m;
      if (r && m && frame->depth.depth_m[i] > 0) {
        dz.push_back(std::fabs(zmin[i] - frame->depth.depth_m[i]));
        dz_signed.push_back(frame->depth.depth_m[i] - zmin[i]);
      }
    }
    if (uni == 0) continue;  // out of view (the mug of 0003/000138)
    const double iou = static_cast<double>(inter) / uni;
    EXPECT_GE(iou, 0.9) << "obj " << frame->gt[g].obj_id;
    ASSERT_FALSE(dz.empty());
    std::nth_element(dz.begin(), dz.begin() + dz.size() / 2, dz.end());
    std::nth_element(dz_signed.begin(), dz_signed.begin() + dz_signed.size() / 2, dz_signed.end());
    std::printf("  obj %2d: IoU %.4f, median |dz| %.2f mm, median dz %.2f mm\n", frame->gt[g].obj_id, iou,
                1000 * dz[dz.size() / 2], 1000 * dz_signed[dz_signed.size() / 2]);
    // The signed median is the renderer's bias (the data README measured -2.8 .. +2.0 mm).
    EXPECT_LE(std::fabs(dz_signed[dz_signed.size() / 2]), 0.005) << "obj " << frame->gt[g].obj_id;
    // The median of |dz| also holds the sensor noise. One real instance exceeds 5 mm for that
    // reason: 052_extra_large_clamp in 0003/000138 (5.46 mm, signed median +2.0 mm).
    const bool noisy = frame->key == FrameKey{3, 138} && frame->gt[g].obj_id == 20;
    EXPECT_LE(dz[dz.size() / 2], noisy ? 0.006 : 0.005) << "obj " << frame->gt[g].obj_id;
  }
}

INSTANTIATE_TEST_SUITE_P(RealFrames, GroundTruthRender,
                         ::testing::Values(FrameKey{0, 1}, FrameKey{1, 1}, FrameKey{2, 1},
                                           FrameKey{3, 138}, FrameKey{49, 1}),
                         [](const ::testing::TestParamInfo<FrameKey>& info) {
                           return "scene" + std::to_string(info.param.scene_id) + "_image" +
                                  std::to_string(info.param.image_id);
                         });

// The ground-truth pose must score in the top 1% of the estimator's own random samples of the
// object's tight box (the weight is what the filter climbs; if GT does not win, it cannot work).
// The checks of detections read each frame's intrinsics without decoding its depth: the same
// intrinsics and size as the decoded frame's, in both layouts.
TEST(RealData, IntrinsicsWithoutDecodingEqualTheFrames) {
  for (const std::string& root : {testing::YcbvDir(), testing::BopDir()}) {
    auto ds = Dataset::Open(root);
    ASSERT_TRUE(ds.ok()) << ds.status().ToString();
    int checked = 0;
    for (const FrameKey& key : (*ds)->Frames()) {
      if (checked == 4) break;
      auto frame = (*ds)->LoadFrame(key);
      auto K = (*ds)->LoadIntrinsics(key);
      ASSERT_TRUE(frame.ok() && K.ok()) << root;
      EXPECT_EQ(K->fx, frame->K.fx);
      EXPECT_EQ(K->fy, frame->K.fy);
      EXPECT_EQ(K->cx, frame->K.cx);
      EXPECT_EQ(K->cy, frame->K.cy);
      EXPECT_EQ(K->width, frame->K.width);
      EXPECT_EQ(K->height, frame->K.height);
      ++checked;
    }
    EXPECT_EQ(checked, 4) << root;
    EXPECT_FALSE((*ds)->LoadIntrinsics(FrameKey{77, 1}).ok());
  }
}

TEST(RealData, GroundTruthPoseScoresInTopOnePercentOfRandomSamples) {
  auto ds = OpenYcbv();
  ASSERT_TRUE(ds);
  EstimatorOptions options;  // the estimator's defaults: its engine, LOD, stride and weight
  options.engine.threads = 2;
  // Turns drawn over the whole sphere only: samples at rest on the table are no random guesses
  // (an upright bottle turned about its axis may match the truth as well as the truth itself).
  options.init.rest_share = 0;
  engine::Context context(options);
  int objects = 0;
  for (FrameKey key : {FrameKey{49, 1}, FrameKey{2, 1}}) {
    auto frame = ds->LoadFrame(key);
    ASSERT_TRUE(frame.ok());
    for (const GtInstance& gt : frame->gt) {
      auto mask = ds->LoadVisibleMask(key, gt);
      auto mesh = ds->LoadMesh(gt.obj_id);
      ASSERT_TRUE(mask.ok() && mesh.ok());
      Detection det{key.scene_id, key.image_id, gt.obj_id, 1.0};
      if (MaskBox(*mask, &det) == 0) continue;  // out of view
      auto scorer = engine::BoxScorer::Create(context, frame->K, frame->depth, *mesh, std::span(&det, 1));
      ASSERT_TRUE(scorer.ok()) << scorer.status().ToString();
      filter::ParticleSet particles;
      engine::InitializeSamples(**scorer, options, 99, &particles);
      // Append the ground-truth pose as the last sample.
      const size_t n = particles.size();
      particles.R_cam_obj.push_back(gt.T_cam_obj.R);
      particles.t_cam_obj_m.push_back(gt.T_cam_obj.t);
      particles.box.push_back(0);
      particles.weight.push_back(0);
      EngineCounters counters;
      (*scorer)->Weigh(&particles, &counters);
      const std::vector<double>& w = particles.weight;
      const double w_gt = w.back();
      const int better = static_cast<int>(std::count_if(w.begin(), w.end() - 1, [&](double x) { return x > w_gt; }));
      EXPECT_LE(better, static_cast<int>(0.01 * n)) << "obj " << gt.obj_id << " in " << key.scene_id << "/"
                                                    << key.image_id << ": w_gt " << w_gt;
      ++objects;
    }
  }
  EXPECT_EQ(objects, 10);
}

// The whole estimator, default options, on two real frames with detector-like boxes (10% jitter,
// 30% distractors). Every object's shape must be found: ADD-S < 4 cm. ADD(-S) < 4 cm must hold
// for at least 60% of the objects whose pose the depth image determines: those all of whose
// depth-equivalent turns (analysis/depth_ambiguity.h at the inlier tolerance, 1 cm on 90% of the
// pixels) lie within 4 cm. The others (here the gelatin box, the sugar box, the tuna can and the
// potted meat can, which flip or turn without changing their depth image) are a coin toss for
// any depth-only estimator; the README reports accuracy on the whole set.
TEST(RealData, EstimationOnTwoFramesMeetsAccuracyBound) {
  auto ds = OpenYcbv();
  ASSERT_TRUE(ds);
  GtDetectionOptions det_options;
  det_options.jitter = 0.1;
  det_options.distractors = 0.3;
  auto all = DetectionsFromGroundTruth(*ds, det_options);
  ASSERT_TRUE(all.ok()) << all.status().ToString();
  std::vector<Detection> dets;
  for (const Detection& d : *all)
    if ((d.scene_id == 49 && d.image_id == 1) || (d.scene_id == 0 && d.image_id == 1)) dets.push_back(d);
  ASSERT_FALSE(dets.empty());

  EstimatorOptions options;  // defaults: 620 samples, <= 50 iterations
  options.engine.threads = 2;
  auto report = RunEstimation(*ds, dets, "test detections", options, nullptr);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  auto eval = Evaluate(*ds, report->results, &dets, EvalOptions{});
  ASSERT_TRUE(eval.ok()) << eval.status().ToString();
  EXPECT_EQ(eval->overall.instances, 7);

  analysis::AmbiguityOptions ambiguity;
  ambiguity.step_deg = 30;
  ambiguity.agree_eps_m = 0.01;
  ambiguity.min_agreement = 0.9;
  int determined = 0, determined_ok = 0;
  for (const auto& e : eval->instances) {
    auto frame = ds->LoadFrame(e.key);
    ASSERT_TRUE(frame.ok());
    const GtInstance& gt = frame->gt[static_cast<size_t>(e.gt_index)];
    auto mask = ds->LoadVisibleMask(e.key, gt);
    auto mesh = ds->LoadMesh(e.obj_id);
    auto points = ds->LoadEvalPoints(e.obj_id);
    ASSERT_TRUE(mask.ok() && mesh.ok() && points.ok());
    Detection box;
    ASSERT_GT(MaskBox(*mask, &box), 0);
    const render::PixelRect rect{int(box.x), int(box.y), int(box.x + box.w), int(box.y + box.h)};
    const auto a = analysis::AnalyzeInstance(frame->K, frame->depth, *mesh, *points, gt.T_cam_obj, rect,
                                             YcbvSymmetricObjectIds().count(e.obj_id) > 0, ambiguity);
    const bool depth_determined = a.ceiling == 1.0;
    determined += depth_determined;
    determined_ok += depth_determined && e.add_or_adds_m < 0.04;
    EXPECT_LT(e.adds_m, 0.04) << "obj " << e.obj_id << " in " << e.key.scene_id << "/" << e.key.image_id;
    std::printf("  obj %2d in %d/%d: ADD(-S) %.1f mm, ADD-S %.1f mm, depth-equivalent turns %d, ceiling %.2f\n",
                e.obj_id, e.key.scene_id, e.key.image_id, 1000 * e.add_or_adds_m, 1000 * e.adds_m, a.equivalent,
                a.ceiling);
  }
  EXPECT_GE(determined, 3);  // the mug, the foam brick and the bowl
  EXPECT_GE(determined_ok, 0.6 * determined) << determined_ok << " of " << determined;
}

// Video 0049, frame 5: the tuna can's own box (top right, the can 0.94 m away and partly hidden)
// and a distractor box of the same size on the flat top of the box below, scored higher by the
// "detector" (the main job's seed-0 boxes). Without the box fit the can is laid there with its
// lid flush with the surface, the lid (larger than the box at that depth) matching the surface
// on nearly every pixel of the box; with it, the pose whose can would reach far past the box
// weighs less and the can is found in its own box.
TEST(RealData, BoxFitKeepsTheTunaCanOutOfADistractorBoxOnAFlatSurface) {
  auto ds = OpenYcbv();
  ASSERT_TRUE(ds);
  const std::vector<Detection> dets = {Detection{49, 5, 6, 0.6769595941185558, 213.078662374869, 345.9861205901099,
                                                 92.59165814580484, 87.55925097634352},
                                       Detection{49, 5, 6, 0.5058579757749193, 433.11176351412195, 93.51788949399034,
                                                 92.59165814580484, 87.55925097634352}};
  for (const double box_fit : {0.8, 0.0}) {
    EstimatorOptions options;  // the defaults
    options.engine.threads = 2;
    options.weight.box_fit = box_fit;
    auto report = RunEstimation(*ds, dets, "test detections", options, nullptr);
    ASSERT_TRUE(report.ok()) << report.status().ToString();
    auto eval = Evaluate(*ds, report->results, &dets, EvalOptions{});
    ASSERT_TRUE(eval.ok()) << eval.status().ToString();
    const auto tuna = std::find_if(eval->instances.begin(), eval->instances.end(),
                                   [](const InstanceEval& e) { return e.obj_id == 6; });
    ASSERT_NE(tuna, eval->instances.end());
    ASSERT_TRUE(tuna->has_result);
    std::printf("  box fit %.1f: ADD-S %.1f mm\n", box_fit, 1000 * tuna->adds_m);
    if (box_fit > 0) {
      EXPECT_LT(tuna->adds_m, 0.01);
    }
  }
}

// Depth ambiguity on real frames: the tuna can turns about its axis without changing its depth
// image (so ADD cannot be had from depth alone), the banana does not, and the bowl's turns are
// all correct under ADD-S.
TEST(RealData, DepthAmbiguityOfCanBananaAndBowl) {
  auto ds = OpenYcbv();
  ASSERT_TRUE(ds);
  analysis::AmbiguityOptions options;
  options.step_deg = 30;
  struct Case {
    FrameKey key;
    int obj_id;
    bool symmetric;
  };
  std::map<int, analysis::InstanceAmbiguity> got;
  for (const Case& c : {Case{{49, 1}, 6, false}, Case{{2, 1}, 10, false}, Case{{49, 1}, 13, true}}) {
    auto frame = ds->LoadFrame(c.key);
    auto mesh = ds->LoadMesh(c.obj_id);
    auto points = ds->LoadEvalPoints(c.obj_id);
    ASSERT_TRUE(frame.ok() && mesh.ok() && points.ok());
    for (const GtInstance& gt : frame->gt) {
      if (gt.obj_id != c.obj_id) continue;
      auto mask = ds->LoadVisibleMask(c.key, gt);
      ASSERT_TRUE(mask.ok());
      Detection box;
      ASSERT_GT(MaskBox(*mask, &box), 0);
      const render::PixelRect rect{int(box.x), int(box.y), int(box.x + box.w), int(box.y + box.h)};
      got[c.obj_id] = analysis::AnalyzeInstance(frame->K, frame->depth, *mesh, *points, gt.T_cam_obj, rect,
                                                c.symmetric, options);
    }
  }
  ASSERT_EQ(got.size(), 3u);
  EXPECT_EQ(got[6].equivalent, 12);  // every 30-degree turn about the can's axis
  EXPECT_GT(got[6].ceiling, 0.2);
  EXPECT_LT(got[6].ceiling, 0.6);
  EXPECT_EQ(got[10].equivalent, 1);  // the banana: only itself
  EXPECT_DOUBLE_EQ(got[10].ceiling, 1.0);
  EXPECT_GE(got[13].equivalent, 12);  // the bowl turns about its axis, scored with ADD-S
  EXPECT_DOUBLE_EQ(got[13].ceiling, 1.0);
}

// The refinement's alignment on the real frames, started at each ground-truth pose and 1 cm and
// 5 degrees from it, lands within a few millimetres of the truth: what is left is where the
// dataset's truth and its depth disagree (analysis/refine_floor.h; 1.8 and 2.0 mm ADD-S on
// average when measured, the offsets consistent per object and video), not a failure to
// converge.
TEST(RealData, RefinementFromTheTruthStaysWithinMillimetresOfIt) {
  auto ds = OpenYcbv();
  ASSERT_TRUE(ds);
  analysis::RefineFloorOptions options;
  options.refine = RefineOptions{};  // the estimator's alignment
  for (double start : {0.0, 10.0}) {
    options.start_mm = start, options.start_deg = 0.5 * start;
    auto report = analysis::AnalyzeRefineFloor(*ds, options);
    ASSERT_TRUE(report.ok()) << report.status().ToString();
    EXPECT_EQ(report->overall.instances, 108);
    EXPECT_LT(report->overall.mean_aligned_mm, 2.5) << "start " << start << " mm";
    EXPECT_GT(report->overall.auc, 0.975) << "start " << start << " mm";
    if (start > 0) {
      EXPECT_GT(report->overall.mean_start_mm, 2 * report->overall.mean_aligned_mm);
    }
    std::printf("  start %.0f mm, %.0f deg: ADD-S %.2f -> %.2f mm (median %.2f), AUC %.2f\n", start,
                options.start_deg, report->overall.mean_start_mm, report->overall.mean_aligned_mm,
                report->overall.median_aligned_mm, 100 * report->overall.auc);
  }
}

}  // namespace
}  // namespace mcpose

// The estimator on a synthetic scene: an asymmetric block rendered by the reference raster core
// in front of a wall, one true box and one distractor box.
#include "mcpose/estimator.h"

#include <cmath>

#include <gtest/gtest.h>

#include "core/rng.h"
#include "render/raster.h"
#include "synthetic_mesh.h"

namespace mcpose {
namespace {

using testing::AddBox;

struct SyntheticScene {
  Intrinsics K{600, 600, 160, 120, 320, 240};
  Mesh mesh;
  SE3 T_gt;
  DepthImage depth;
};

SyntheticScene MakeScene() {
  SyntheticScene s;
  // An L of two blocks: no rotational symmetry.
  AddBox(&s.mesh, {-0.05f, -0.03f, -0.02f}, {0.05f, 0.03f, 0.02f});
  AddBox(&s.mesh, {0.02f, 0.03f, -0.02f}, {0.05f, 0.08f, 0.02f});
  s.T_gt = SE3(ExpSO3(Eigen::Vector3d(0.4, -0.3, 0.5)), Eigen::Vector3d(-0.02, 0.01, 0.7));
  // Render the object in front of an unstructured background (random depths in 0.9-1.5 m):
  // a planar wall would let a flat face pressed onto it score like the object itself.
  render::RasterParams p;
  p.fx = 600, p.fy = 600, p.cx = 160, p.cy = 120;
  p.box = render::PixelRect{0, 0, 320, 240};
  std::vector<render::ScreenVertex> sv(s.mesh.vertices_m.size());
  render::ProjectVertices(s.mesh.vertices_m, s.T_gt.R.cast<float>(), s.T_gt.t.cast<float>(), p, sv);
  s.depth.width = 320, s.depth.height = 240;
  s.depth.depth_m.assign(320 * 240, INFINITY);
  render::RasterizeDepthReference(sv, s.mesh.triangles, p, s.depth.depth_m.data(), nullptr);
  Rng rng(1, 2);
  for (float& z : s.depth.depth_m)
    if (std::isinf(z)) z = static_cast<float>(rng.Uniform(0.9, 1.5));
  return s;
}

// The tight box of the rendered object (its pixels nearer than the background), with `score`.
Detection TightBox(const SyntheticScene& s, double score) {
  int x0 = 320, y0 = 240, x1 = 0, y1 = 0;
  for (int y = 0; y < 240; ++y)
    for (int x = 0; x < 320; ++x)
      if (s.depth.at(x, y) < 0.85f) x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
  return Detection{1, 1, 7, score, double(x0), double(y0), double(x1 - x0 + 1), double(y1 - y0 + 1)};
}

std::vector<double> MeanWeights(const ObjectEstimate& e) {
  std::vector<double> w;
  for (const IterationSummary& it : e.iterations) w.push_back(it.mean_weight);
  return w;
}

TEST(Estimator, RecoversSyntheticPoseAndIgnoresDistractor) {
  const SyntheticScene s = MakeScene();
  // Tight box of the rendered object, and a distractor box of the same size elsewhere.
  const Detection tight = TightBox(s, 0.6);
  const double w = tight.w, h = tight.h;
  std::vector<Detection> boxes = {tight, Detection{1, 1, 7, 0.5, 320 - w - 1, 0, w, h}};
  EstimatorOptions options;
  options.samples = 400;
  options.max_iterations = 40;
  options.engine.threads = 2;
  auto est = Estimator::Create(options);
  ASSERT_TRUE(est.ok());
  auto r = (*est)->Estimate(s.K, s.depth, s.mesh, boxes, 3);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(r->best_box, 0);
  ASSERT_GE(r->iterations.size(), 2u);
  EXPECT_GT(r->iterations.back().mean_weight, r->iterations.front().mean_weight);
  for (const IterationSummary& it : r->iterations) EXPECT_GE(it.best_weight, it.mean_weight);
  EXPECT_LT((r->T_cam_obj.t - s.T_gt.t).norm(), 0.01);
  // No rotation bound: at 400 samples this depth-only fit often settles on the mirrored L
  // (180 degrees about model x; same main block, small block on the other side), a local
  // optimum of the weight. Real-data accuracy is tested in tests/real_data_test.cc.
  // Counters: every triangle has one fate; draws were counted.
  const EngineCounters c = r->Totals();
  const int64_t iterations = static_cast<int64_t>(r->iterations.size());
  // The first generation holds init.wide times the samples.
  EXPECT_EQ(c.triangles_in, int64_t{24} * options.samples * (options.init.wide + iterations - 1));
  EXPECT_EQ(c.culled_backface + c.culled_degenerate + c.culled_outside_box + c.culled_near +
                c.culled_between_pixels + c.triangles_rasterized,
            c.triangles_in);
  // Every resampling draws the samples less the elite, which pass unchanged.
  const int64_t elite = std::lround(options.resample.elite_share * options.samples);
  EXPECT_GT(elite, 0);
  EXPECT_EQ(c.cdf_draws, (options.samples - elite) * (iterations - 1));
  EXPECT_GE(c.cdf_reads, 2 * c.cdf_draws);  // each draw reads its table entry and a CDF entry
  EXPECT_LT(c.cdf_reads, 20 * c.cdf_draws);
  // The depth distributor read the union of the two boxes' grids once.
  EXPECT_GT(r->depth_pixels_read, 0);
  EXPECT_LE(r->depth_pixels_read, int64_t{320} * 240);
}

TEST(Estimator, SameResultAtAnyThreadCountAndForTheFixedPointCore) {
  const SyntheticScene s = MakeScene();
  std::vector<Detection> boxes = {Detection{1, 1, 7, 0.9, 100, 60, 120, 120}};
  for (double flip_rate : {0.0, 0.1}) {
    ObjectEstimate first;
    for (int threads : {1, 2, 4}) {
      EstimatorOptions options;
      options.samples = 128;
      options.max_iterations = 8;
      options.engine.threads = threads;
      options.diffusion.flip_rate = flip_rate;
      auto r = (*Estimator::Create(options))->Estimate(s.K, s.depth, s.mesh, boxes, 11);
      ASSERT_TRUE(r.ok());
      if (threads == 1) {
        first = *r;
        continue;
      }
      EXPECT_EQ(r->T_cam_obj.R, first.T_cam_obj.R) << flip_rate;
      EXPECT_EQ(r->T_cam_obj.t, first.T_cam_obj.t) << flip_rate;
      EXPECT_EQ(MeanWeights(*r), MeanWeights(first)) << flip_rate;
    }
  }
  EstimatorOptions fixed;
  fixed.samples = 128;
  fixed.max_iterations = 1;
  fixed.engine.backend = RasterBackend::kFixedPoint;
  EstimatorOptions scalar = fixed;
  scalar.engine.backend = RasterBackend::kScalar;
  scalar.engine.DropUnusableFeatures();
  auto a = (*Estimator::Create(fixed))->Estimate(s.K, s.depth, s.mesh, boxes, 11);
  auto b = (*Estimator::Create(scalar))->Estimate(s.K, s.depth, s.mesh, boxes, 11);
  ASSERT_TRUE(a.ok() && b.ok());
  // Same samples, scored by both cores: mean weights within 0.5%.
  EXPECT_NEAR(a->iterations[0].mean_weight, b->iterations[0].mean_weight, 0.005 * b->iterations[0].mean_weight);
}

// How often 8 runs (streams 0-7) find the synthetic L within 0.2 rad, with `options`.
int RunsThatFindTheL(const SyntheticScene& s, const EstimatorOptions& options) {
  const std::vector<Detection> boxes = {TightBox(s, 0.9)};
  auto est = Estimator::Create(options);
  EXPECT_TRUE(est.ok());
  if (!est.ok()) return -1;
  int found = 0;
  for (uint64_t stream = 0; stream < 8; ++stream) {
    auto r = (*est)->Estimate(s.K, s.depth, s.mesh, boxes, stream);
    EXPECT_TRUE(r.ok());
    if (r.ok()) found += LogSO3(r->T_cam_obj.R * s.T_gt.R.transpose()).norm() < 0.2;
  }
  return found;
}

// With few samples (100, 20 iterations), the synthetic L's depth-only fit often settles on the
// mirrored L (a half turn about model x) with the paper's first generation and resampling; the
// wide first generation and the elite find it in most runs (7 of 8 against 2 of 8 when
// written; every run's seed is fixed, so the counts are too).
TEST(Estimator, TheWideFirstGenerationAndTheEliteFindTheL) {
  const SyntheticScene s = MakeScene();
  EstimatorOptions options;
  options.samples = 100;
  options.max_iterations = 20;
  options.engine.threads = 2;
  const int found = RunsThatFindTheL(s, options);
  options.init.wide = 1;
  options.resample.elite_share = 0;
  const int paper = RunsThatFindTheL(s, options);
  EXPECT_GE(found, 6);
  EXPECT_GE(found - paper, 3);
}

// Flip moves: with the paper's first generation and resampling, the synthetic L is found in
// more runs with them than without (4 of 8 against 2 of 8 when written).
TEST(Estimator, FlipMovesFindTheLMoreOften) {
  const SyntheticScene s = MakeScene();
  const std::vector<Detection> boxes = {TightBox(s, 0.9)};
  int found[2] = {0, 0};
  for (int f = 0; f < 2; ++f) {
    EstimatorOptions options;
    options.samples = 400;
    options.max_iterations = 40;
    options.engine.threads = 2;
    options.init.wide = 1;
    options.resample.elite_share = 0;
    options.diffusion.flip_rate = f ? 0.05 : 0.0;
    auto est = Estimator::Create(options);
    ASSERT_TRUE(est.ok());
    for (uint64_t stream = 0; stream < 8; ++stream) {
      auto r = (*est)->Estimate(s.K, s.depth, s.mesh, boxes, stream);
      ASSERT_TRUE(r.ok());
      const double angle = LogSO3(r->T_cam_obj.R * s.T_gt.R.transpose()).norm();
      found[f] += angle < 0.2;
    }
  }
  EXPECT_GT(found[1], found[0]);
}

// The float-simd engine is the scalar reference a vector at a time: the same counts, so the
// same weights and the same pose, every iteration, with or without back faces.
TEST(Estimator, FloatSimdEngineGivesTheScalarEnginesPoses) {
  const SyntheticScene s = MakeScene();
  std::vector<Detection> boxes = {Detection{1, 1, 7, 0.9, 100, 60, 120, 120}};
  for (bool cull : {true, false}) {
    EstimatorOptions scalar;
    scalar.samples = 128;
    scalar.max_iterations = 6;
    scalar.engine = EngineOptions::Reference();
    scalar.engine.backface_culling = cull;
    EstimatorOptions float_simd = scalar;
    float_simd.engine.backend = RasterBackend::kFloatSimd;
    auto a = (*Estimator::Create(scalar))->Estimate(s.K, s.depth, s.mesh, boxes, 5);
    auto b = (*Estimator::Create(float_simd))->Estimate(s.K, s.depth, s.mesh, boxes, 5);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(b->T_cam_obj.R, a->T_cam_obj.R) << "cull " << cull;
    EXPECT_EQ(b->T_cam_obj.t, a->T_cam_obj.t) << "cull " << cull;
    EXPECT_EQ(MeanWeights(*b), MeanWeights(*a)) << "cull " << cull;
    EXPECT_FALSE(a->iterations.empty());
  }
}

TEST(Estimator, RejectsBadBoxesAndMismatchedInputs) {
  const SyntheticScene s = MakeScene();
  auto est = std::move(Estimator::Create(EstimatorOptions{})).value();
  auto check = [&](std::vector<Detection> boxes, const std::string& phrase) {
    auto r = est->Estimate(s.K, s.depth, s.mesh, boxes, 0);
    ASSERT_FALSE(r.ok()) << phrase;
    EXPECT_NE(r.status().message().find(phrase), std::string::npos) << r.status().message();
  };
  check({}, "no boxes");
  check({Detection{1, 1, 7, 0.9, 500, 10, 20, 20}}, "outside");
  check({Detection{1, 1, 7, 0.9, 10, 10, 0, 20}}, "positive");
  check({Detection{1, 1, 7, NAN, 10, 10, 20, 20}}, "score");
  check({Detection{1, 1, 7, 0.9, 10, 10, 20, 20}, Detection{1, 1, 8, 0.9, 10, 10, 20, 20}}, "different classes");
  Intrinsics bad = s.K;
  bad.fx = 0;
  auto r = est->Estimate(bad, s.depth, s.mesh, std::vector<Detection>{Detection{1, 1, 7, 0.9, 10, 10, 20, 20}}, 0);
  EXPECT_FALSE(r.ok());
}

}  // namespace
}  // namespace mcpose

#include "engine/box_scorer.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "core/rng.h"
#include "engine/initialize.h"
#include "hw/rtl_core.h"
#include "score/box_fit.h"
#include "score/weight.h"
#include "synthetic_mesh.h"

namespace mcpose::engine {
namespace {

struct Scene {
  Intrinsics K{600, 600, 160, 120, 320, 240};
  DepthImage depth;
  Mesh mesh = testing::Blob();
};

Scene MakeScene() {
  Scene s;
  s.depth.width = 320, s.depth.height = 240;
  s.depth.depth_m.resize(320 * 240);
  Rng rng(4, 4);
  for (float& z : s.depth.depth_m) z = static_cast<float>(rng.Uniform(0.5, 0.7));
  return s;
}

TEST(BoxScorer, PreparesEachBoxAsTheOptionsSay) {
  const Scene s = MakeScene();
  EstimatorOptions o;
  o.engine.pixel_stride = 2;
  o.engine.max_grid_pixels = 1000;
  Context context(o);
  // A small box at the grid stride, a large one sampled more coarsely; they overlap.
  const std::vector<Detection> boxes = {Detection{1, 1, 5, 0.9, 100, 80, 40, 30},
                                        Detection{1, 1, 5, 0.4, 90.5, 70, 150, 120}};
  auto scorer = BoxScorer::Create(context, s.K, s.depth, s.mesh, boxes);
  ASSERT_TRUE(scorer.ok()) << scorer.status().ToString();
  const BoxScorer& b = **scorer;
  EXPECT_EQ(b.num_boxes(), 2);
  EXPECT_EQ(b.obj_id(), 5);
  EXPECT_EQ(b.box_observation(0).stride, 2);
  EXPECT_EQ(b.box_observation(1).stride, 5);  // 151 x 120 pixels: 31 x 24 grid pixels at stride 5
  EXPECT_EQ(b.box_observation(1).image_rect.x0, 90);  // rounded outwards
  EXPECT_EQ(b.box_observation(1).image_rect.x1, 241);
  EXPECT_EQ(b.box_observation(0).score, 0.9);
  // Both boxes render a LOD level of the blob, with its clusters.
  ASSERT_NE(b.box_level(0), nullptr);
  EXPECT_EQ(&b.box_mesh(0), &b.box_level(0)->mesh);
  EXPECT_LE(b.box_mesh(0).triangles.size(), s.mesh.triangles.size());
  // The depth distributor reads the union of the two sample grids.
  const int64_t small = 20 * 15, large = 31 * 24;
  EXPECT_GT(b.depth_pixels_read(), large);
  EXPECT_LT(b.depth_pixels_read(), small + large);
}

// The hw backend's depth bounds hold eps: a new inlier threshold gives the counts of a scorer
// made with it (the refinement's acceptance counts at its own eps).
TEST(BoxScorer, HardwareBoundsFollowTheInlierThreshold) {
  const Scene s = MakeScene();
  EstimatorOptions o;
  o.engine.backend = RasterBackend::kHardware;
  o.engine.DropUnusableFeatures();
  EstimatorOptions o_fine = o;
  o_fine.weight.eps_m = 0.004;
  Context context(o), context_fine(o_fine);
  const std::vector<Detection> boxes = {Detection{1, 1, 5, 0.9, 100, 80, 80, 60}};
  auto scorer = BoxScorer::Create(context, s.K, s.depth, s.mesh, boxes);
  auto fine = BoxScorer::Create(context_fine, s.K, s.depth, s.mesh, boxes);
  ASSERT_TRUE(scorer.ok() && fine.ok());
  filter::ParticleSet particles;
  InitializeSamples(**scorer, o, 1, &particles);
  std::vector<score::InlierCounts> a(particles.size()), b(particles.size()), c(particles.size());
  EngineCounters counters;
  (*scorer)->Count(particles, a, &counters);
  (*scorer)->set_inlier_threshold(0.004f);
  (*scorer)->Count(particles, b, &counters);
  (*fine)->Count(particles, c, &counters);
  EXPECT_EQ(b, c);
  int64_t coarse = 0, narrow = 0;
  for (size_t i = 0; i < a.size(); ++i) coarse += a[i].inliers, narrow += b[i].inliers;
  EXPECT_LT(narrow, coarse);
  EXPECT_GT(narrow, 0);
}

// The rtl backend's simulated core has fixed memories: a mesh with more vertices than its
// vertex RAM is refused with a message that says so.
TEST(BoxScorer, RtlRefusesAMeshBeyondTheSimulatedCoresVertexMemory) {
  if (!RtlBackendAvailable()) GTEST_SKIP() << "built without Verilator: no rtl backend";
  const Scene s = MakeScene();
  EstimatorOptions o;
  o.engine.backend = RasterBackend::kRtl;
  o.engine.lod_error_px = 0;  // the full mesh, not a coarser level
  o.engine.DropUnusableFeatures();
  Mesh big = s.mesh;
  while (big.vertices_m.size() <= (size_t{1} << hw::kRtlVertexIndexBits)) big.vertices_m.push_back(big.vertices_m[0]);
  Context context(o);
  const std::vector<Detection> boxes = {Detection{1, 1, 5, 0.9, 100, 80, 80, 60}};
  auto refused = BoxScorer::Create(context, s.K, s.depth, big, boxes);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.status().message().find("vertex memory"), std::string::npos) << refused.status().message();
  EXPECT_TRUE(BoxScorer::Create(context, s.K, s.depth, s.mesh, boxes).ok());
}

// The weight of the counts, times the box-fit factor of the pose (score/box_fit.h); with the
// box fit off, the weight of the counts alone. The box is smaller than the blob at the
// samples' depths, so some samples are scaled down.
TEST(BoxScorer, WeighGivesEachSampleTheWeightOfItsCountsAndBoxFit) {
  const Scene s = MakeScene();
  const Detection box{1, 1, 5, 0.8, 130, 90, 60, 60};
  const std::vector<Eigen::Vector3d> extremes = score::ExtremePoints(s.mesh);
  for (const double box_fit : {0.8, 0.0}) {
    SCOPED_TRACE(box_fit);
    EstimatorOptions o;
    o.samples = 64;
    o.weight.box_fit = box_fit;
    Context context(o);
    auto scorer = BoxScorer::Create(context, s.K, s.depth, s.mesh, std::span(&box, 1));
    ASSERT_TRUE(scorer.ok());
    filter::ParticleSet p;
    InitializeSamples(**scorer, o, 3, &p);
    std::vector<score::InlierCounts> counts(p.size());
    EngineCounters c1, c2;
    (*scorer)->Count(p, counts, &c1);
    (*scorer)->Weigh(&p, &c2);
    int scaled = 0;
    for (size_t i = 0; i < p.size(); ++i) {
      const double share = score::BoxFitShare(extremes, p.R_cam_obj[i], p.t_cam_obj_m[i], s.K, score::FitBoxOf(box, s.K));
      const double factor = score::BoxFitFactor(share, box_fit);
      scaled += factor < 1;
      EXPECT_EQ(p.weight[i], score::Weight(counts[i], 0.8, o.weight) * factor);
    }
    if (box_fit > 0) {
      EXPECT_GT(scaled, 0);
    }
    EXPECT_EQ(c1.fragments, c2.fragments);
    EXPECT_GT(c1.fragments, 0);
    EXPECT_EQ(c1.triangles_full, static_cast<int64_t>(s.mesh.triangles.size()) * o.samples);
  }
}

TEST(BoxScorer, RejectsBadInputNamingTheBox) {
  const Scene s = MakeScene();
  Context context(EstimatorOptions{});
  auto check = [&](std::vector<Detection> boxes, const std::string& phrase) {
    auto r = BoxScorer::Create(context, s.K, s.depth, s.mesh, boxes);
    ASSERT_FALSE(r.ok()) << phrase;
    EXPECT_NE(r.status().message().find(phrase), std::string::npos) << r.status().message();
  };
  check({}, "no boxes");
  check({Detection{1, 1, 5, 0.9, 500, 10, 20, 20}}, "box 0 of obj_id 5: box [500, 10, 20, 20] lies outside");
  check({Detection{1, 1, 5, 0.9, 10, 10, 20, 20}, Detection{1, 1, 5, -1, 10, 10, 20, 20}}, "box 1 of obj_id 5: score");
  check({Detection{1, 1, 5, 0.9, 10, 10, INFINITY, 20}}, "finite");
  check({Detection{1, 1, 5, 3, 10, 10, 20, 20}}, "score must be a finite number in [0, 1]");
  check({Detection{1, 1, 5, 0.9, 10, 10, 20, 20}, Detection{1, 1, 6, 0.9, 10, 10, 20, 20}}, "different classes");
  DepthImage small = s.depth;
  small.width = 100;
  EXPECT_FALSE(BoxScorer::Create(context, s.K, small, s.mesh, std::vector<Detection>{{1, 1, 5, 0.9, 1, 1, 5, 5}}).ok());
  EXPECT_FALSE(BoxScorer::Create(context, s.K, s.depth, Mesh{}, std::vector<Detection>{{1, 1, 5, 0.9, 1, 1, 5, 5}}).ok());
}

}  // namespace
}  // namespace mcpose::engine

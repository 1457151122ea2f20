// The loop's generations: a wide first one, an elite that passes unchanged.
#include "engine/filter_loop.h"

#include <algorithm>
#include <numeric>
#include <vector>

#include <gtest/gtest.h>

#include "engine/context.h"
#include "synthetic_mesh.h"

namespace mcpose::engine {
namespace {

struct Generation {
  std::vector<SE3> poses;
  std::vector<double> weights;
};

// Runs the loop on a 320 x 240 frame (a slab's worth of near surface at 0.6 m in the box, a
// background at 0.9 m; the slab 12 x 4 x 2 cm) for options.max_iterations, tau out of reach,
// and records each weighed generation.
std::vector<Generation> RunLoop(const EstimatorOptions& o, ObjectEstimate* estimate) {
  const Intrinsics K{600, 600, 160, 120, 320, 240};
  DepthImage depth;
  depth.width = 320, depth.height = 240;
  depth.depth_m.assign(320 * 240, 0.9f);
  for (int y = 80; y < 140; ++y)
    for (int x = 110; x < 200; ++x) depth.depth_m[static_cast<size_t>(y) * 320 + x] = 0.6f;
  Mesh mesh;
  testing::AddBox(&mesh, Eigen::Vector3f(-0.06f, -0.02f, -0.01f), Eigen::Vector3f(0.06f, 0.02f, 0.01f));
  Context context(o);
  const std::vector<Detection> boxes = {Detection{1, 1, 5, 0.9, 100, 60, 120, 100}};
  auto scorer = BoxScorer::Create(context, K, depth, mesh, boxes);
  EXPECT_TRUE(scorer.ok()) << scorer.status().ToString();
  std::vector<Generation> generations;
  if (!scorer.ok()) return generations;
  *estimate = RunFilter(**scorer, o, context.pool(), 3, [&](int, const filter::ParticleSet& p) {
    Generation& g = generations.emplace_back();
    for (size_t i = 0; i < p.size(); ++i) g.poses.push_back(p.Pose(i)), g.weights.push_back(p.weight[i]);
  });
  return generations;
}

// 100 samples, 4 iterations, every one run; the given first generation and elite.
EstimatorOptions Options(int wide, double elite_share) {
  EstimatorOptions o;
  o.samples = 100;
  o.max_iterations = 4;
  o.tau = 2;  // never reached
  o.init.wide = wide;
  o.resample.elite_share = elite_share;
  return o;
}

TEST(FilterLoop, TheFirstGenerationIsWideAndEveryLaterOneHasTheSamples) {
  const EstimatorOptions o = Options(5, 0.1);
  ObjectEstimate e;
  const std::vector<Generation> g = RunLoop(o, &e);
  ASSERT_EQ(g.size(), 4u);
  EXPECT_EQ(g[0].poses.size(), 500u);
  for (size_t k = 1; k < g.size(); ++k) EXPECT_EQ(g[k].poses.size(), 100u) << k;
  // Each resampling draws the generation less its elite of 10.
  ASSERT_EQ(e.iterations.size(), 4u);
  for (size_t k = 0; k + 1 < e.iterations.size(); ++k) EXPECT_EQ(e.iterations[k].counters.cdf_draws, 90) << k;
  EXPECT_EQ(e.iterations.back().counters.cdf_draws, 0);
}

TEST(FilterLoop, TheEliteOfAGenerationLeadsTheNextUnchangedAndKeepsItsWeight) {
  const EstimatorOptions o = Options(2, 0.15);
  ASSERT_EQ(EliteCount(o, o.samples), 15);
  ObjectEstimate e;
  const std::vector<Generation> g = RunLoop(o, &e);
  ASSERT_EQ(g.size(), 4u);
  for (size_t k = 0; k + 1 < g.size(); ++k) {
    std::vector<int> order(g[k].weights.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return g[k].weights[a] > g[k].weights[b]; });
    for (int i = 0; i < 15; ++i) {
      const SE3& parent = g[k].poses[static_cast<size_t>(order[static_cast<size_t>(i)])];
      const SE3& child = g[k + 1].poses[static_cast<size_t>(i)];
      EXPECT_EQ(child.R, parent.R) << "generation " << k + 1 << ", elite " << i;
      EXPECT_EQ(child.t, parent.t) << "generation " << k + 1 << ", elite " << i;
      EXPECT_EQ(g[k + 1].weights[static_cast<size_t>(i)], g[k].weights[static_cast<size_t>(order[static_cast<size_t>(i)])]);
    }
    // The drawn samples are diffused: none is a copy of its parent.
    for (size_t i = 15; i < g[k + 1].poses.size(); ++i)
      for (const SE3& parent : g[k].poses) ASSERT_FALSE(g[k + 1].poses[i].t == parent.t) << k + 1 << " " << i;
  }
  // The best weight never falls from one generation to the next.
  for (size_t k = 0; k + 1 < g.size(); ++k)
    EXPECT_GE(*std::max_element(g[k + 1].weights.begin(), g[k + 1].weights.end()),
              *std::max_element(g[k].weights.begin(), g[k].weights.end()));
}

TEST(FilterLoop, WithoutEliteOrWideFirstGenerationEverySampleIsDrawn) {
  const EstimatorOptions o = Options(1, 0);
  ObjectEstimate e;
  const std::vector<Generation> g = RunLoop(o, &e);
  ASSERT_EQ(g.size(), 4u);
  for (const Generation& gen : g) EXPECT_EQ(gen.poses.size(), 100u);
  for (size_t k = 0; k + 1 < e.iterations.size(); ++k) EXPECT_EQ(e.iterations[k].counters.cdf_draws, 100);
  for (size_t k = 0; k + 1 < g.size(); ++k)
    for (const SE3& child : g[k + 1].poses)
      for (const SE3& parent : g[k].poses) ASSERT_FALSE(child.t == parent.t);
}

}  // namespace
}  // namespace mcpose::engine

// Every backend against the scalar reference on random poses of a bumpy blob over random
// observed depth, through the raster cores at 1 to 3 threads: float-simd is bit-identical to
// the reference, simd to fixed, and fixed agrees with the reference to a fraction of a percent
// (its coverage and depth come from the snapped triangle). Clusters and batched setup keep the
// fixed-point counts.
#include "backends/backend.h"

#include <cmath>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "core/rng.h"
#include "engine/raster_cores.h"
#include "filter/particles.h"
#include "mcpose/se3.h"
#include "render/lod.h"
#include "synthetic_mesh.h"

namespace mcpose::backends {
namespace {

struct Scene {
  Intrinsics K{1066.778, 1067.487, 312.9869, 241.3109, 640, 480};
  Mesh mesh = testing::Blob();
  std::vector<score::BoxObservation> boxes;
  filter::ParticleSet particles;
};

// Two boxes (one at stride 2) of random observed depth near the blob's distance, 1-D or 3-D,
// and `n` random poses in front of the camera, each in one of the boxes.
Scene MakeScene(int n, InlierMode mode, uint64_t seed) {
  Scene s;
  Rng rng(seed, 1);
  DepthImage depth;
  depth.width = 640, depth.height = 480;
  depth.depth_m.resize(640 * 480);
  for (float& z : depth.depth_m) z = rng.Uniform() < 0.1 ? 0.f : static_cast<float>(rng.Uniform(0.55, 0.65));
  s.boxes.push_back(score::DistributeBox(depth, s.K, render::PixelRect{250, 180, 380, 300}, 0.9, mode, 1));
  s.boxes.push_back(score::DistributeBox(depth, s.K, render::PixelRect{240, 170, 400, 320}, 0.5, mode, 2));
  s.particles.Resize(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    s.particles.R_cam_obj[i] = filter::UniformRotation(rng.Uniform(), rng.Uniform(), rng.Uniform());
    s.particles.t_cam_obj_m[i] = Eigen::Vector3d(rng.Uniform(-0.04, 0.04), rng.Uniform(-0.04, 0.04), rng.Uniform(0.5, 0.7));
    s.particles.box[i] = i % 2;
  }
  return s;
}

std::vector<score::InlierCounts> Score(RasterBackend backend, int threads, std::span<const BoxTarget> targets,
                                       const SampleSettings& settings, const filter::ParticleSet& particles,
                                       RasterCounters* stats = nullptr) {
  engine::RasterCores cores(threads, backend);
  std::vector<score::InlierCounts> counts(particles.size());
  cores.Score(targets, settings, particles, counts, stats);
  return counts;
}

TEST(Backends, EachMatchesItsReferenceOnRandomPosesAtAnyThreadCount) {
  for (InlierMode mode : {InlierMode::k1D, InlierMode::k3D}) {
    for (bool cull : {true, false}) {
      const Scene s = MakeScene(mode == InlierMode::k3D ? 60 : 240, mode, 7 + cull);
      const std::vector<BoxTarget> targets = {{&s.boxes[0], &s.mesh, nullptr}, {&s.boxes[1], &s.mesh, nullptr}};
      SampleSettings settings;
      settings.inlier_mode = mode;
      settings.cull_backfaces = cull;
      settings.batched_setup = false;
      RasterCounters ref_stats;
      const auto reference = Score(RasterBackend::kScalar, 1, targets, settings, s.particles, &ref_stats);
      int64_t rendered = 0, diff = 0;
      for (const auto& c : reference) rendered += c.rendered;
      ASSERT_GT(rendered, 1000);
      for (int threads : {1, 2, 3}) {
        RasterCounters float_stats;
        EXPECT_EQ(Score(RasterBackend::kFloatSimd, threads, targets, settings, s.particles, &float_stats), reference);
        EXPECT_EQ(float_stats, ref_stats);
        const auto fixed = Score(RasterBackend::kFixedPoint, threads, targets, settings, s.particles);
        for (bool batched : {false, true}) {
          SampleSettings b = settings;
          b.batched_setup = batched;
          EXPECT_EQ(Score(RasterBackend::kFixedPoint, threads, targets, b, s.particles), fixed);
          EXPECT_EQ(Score(RasterBackend::kSimd, threads, targets, b, s.particles), fixed);
        }
        if (threads == 1)
          for (size_t i = 0; i < fixed.size(); ++i)
            diff += std::abs(fixed[i].inliers - reference[i].inliers) + std::abs(fixed[i].rendered - reference[i].rendered);
      }
      EXPECT_LE(diff, 0.01 * rendered) << "mode " << int(mode) << " cull " << cull;
    }
  }
}

TEST(Backends, ClusterCullingKeepsTheFixedPointCounts) {
  const Scene s = MakeScene(200, InlierMode::k1D, 3);
  const render::LodChain chain = render::LodChain::Build(s.mesh);
  const render::LodLevel& level = chain.level(chain.num_levels() / 2);
  const std::vector<BoxTarget> plain = {{&s.boxes[0], &level.mesh, nullptr}, {&s.boxes[1], &level.mesh, nullptr}};
  const std::vector<BoxTarget> clustered = {{&s.boxes[0], &level.mesh, &level.clusters},
                                            {&s.boxes[1], &level.mesh, &level.clusters}};
  for (RasterBackend backend : {RasterBackend::kFixedPoint, RasterBackend::kSimd}) {
    SampleSettings settings;
    RasterCounters plain_stats, clustered_stats;
    const auto a = Score(backend, 2, plain, settings, s.particles, &plain_stats);
    const auto b = Score(backend, 2, clustered, settings, s.particles, &clustered_stats);
    EXPECT_EQ(a, b) << RasterBackendName(backend);
    EXPECT_GT(clustered_stats.clusters_culled_backface + clustered_stats.clusters_culled_outside_box, 0);
    EXPECT_EQ(clustered_stats.triangles_in, plain_stats.triangles_in);
  }
}

// A scene the hardware's backends can score: the boxes' bounds, the model in the core's formats.
struct HardwareScene {
  Scene scene;
  std::vector<hw::ModelVertex> model;
  std::vector<BoxTarget> targets;
  SampleSettings settings;
};
std::unique_ptr<HardwareScene> MakeHardwareScene(int n, uint64_t seed, bool cull) {
  auto h = std::make_unique<HardwareScene>();
  h->scene = MakeScene(n, InlierMode::k1D, seed);
  const float eps = 0.01f;
  for (score::BoxObservation& box : h->scene.boxes) score::AddDepthBounds(&box, eps);
  EXPECT_TRUE(hw::QuantizeModel(h->scene.mesh.vertices_m, &h->model));
  for (score::BoxObservation& box : h->scene.boxes) h->targets.push_back({&box, &h->scene.mesh, nullptr});
  for (BoxTarget& t : h->targets) t.hw_model = &h->model;
  h->settings.eps_m = eps;
  h->settings.cull_backfaces = cull;
  h->settings.batched_setup = false;
  return h;
}

// The hardware numerics (hw/) against the float reference: the same pixels to a fraction of a
// percent (coverage on its own 1/16-pixel grid, depth from its IZ plane), the same counts at any
// thread count.
TEST(Backends, HardwareAgreesWithTheReferenceOnRandomPoses) {
  for (bool cull : {true, false}) {
    const auto h = MakeHardwareScene(240, 21 + cull, cull);
    const Scene& s = h->scene;
    const auto& targets = h->targets;
    const SampleSettings& settings = h->settings;
    RasterCounters ref_stats, hw_stats;
    const auto reference = Score(RasterBackend::kScalar, 1, targets, settings, s.particles, &ref_stats);
    const auto hw = Score(RasterBackend::kHardware, 1, targets, settings, s.particles, &hw_stats);
    int64_t rendered = 0, inliers = 0, diff_rendered = 0, diff_inliers = 0, diff_occluded = 0;
    for (size_t i = 0; i < hw.size(); ++i) {
      rendered += reference[i].rendered, inliers += reference[i].inliers;
      diff_rendered += std::abs(hw[i].rendered - reference[i].rendered);
      diff_inliers += std::abs(hw[i].inliers - reference[i].inliers);
      diff_occluded += std::abs(hw[i].occluded - reference[i].occluded);
      EXPECT_EQ(hw[i].observed, reference[i].observed);
    }
    ASSERT_GT(inliers, 1000);
    EXPECT_LE(diff_rendered, 0.01 * rendered) << "cull " << cull;
    EXPECT_LE(diff_inliers, 0.01 * inliers) << "cull " << cull;
    EXPECT_LE(diff_occluded, 0.01 * rendered) << "cull " << cull;
    EXPECT_EQ(hw_stats.triangles_in, ref_stats.triangles_in);
    EXPECT_EQ(hw_stats.culled_hw_range, 0);
    EXPECT_EQ(hw_stats.triangles_rasterized + hw_stats.culled_backface + hw_stats.culled_degenerate +
                  hw_stats.culled_outside_box + hw_stats.culled_near + hw_stats.culled_between_pixels +
                  hw_stats.culled_hw_range,
              hw_stats.triangles_in);
    for (int threads : {2, 3}) EXPECT_EQ(Score(RasterBackend::kHardware, threads, targets, settings, s.particles), hw);
  }
}

// The RTL (hw/rtl/raster_core.sv through Verilator) against the C++ model of its numerics: the
// same counts, sample for sample, on random poses of both boxes, culling on and off.
TEST(Backends, RtlGivesTheHardwareModelsCounts) {
  if (!RtlBackendAvailable()) GTEST_SKIP() << "built without Verilator: no rtl backend";
  for (bool cull : {true, false}) {
    const auto h = MakeHardwareScene(40, 31 + cull, cull);
    RasterCounters hw_stats, rtl_stats;
    const auto hw = Score(RasterBackend::kHardware, 1, h->targets, h->settings, h->scene.particles, &hw_stats);
    const auto rtl = Score(RasterBackend::kRtl, 2, h->targets, h->settings, h->scene.particles, &rtl_stats);
    EXPECT_EQ(rtl, hw) << "cull " << cull;
    EXPECT_EQ(rtl_stats.triangles_in, hw_stats.triangles_in);
    EXPECT_EQ(rtl_stats.triangles_rasterized, hw_stats.triangles_rasterized);
    EXPECT_EQ(rtl_stats.fragments, hw_stats.fragments);
    EXPECT_GT(hw_stats.fragments, 0);
  }
}

TEST(Backends, RegistryGivesEachKind) {
  for (RasterBackend kind : {RasterBackend::kScalar, RasterBackend::kFloatSimd, RasterBackend::kFixedPoint,
                             RasterBackend::kSimd, RasterBackend::kHardware})
    EXPECT_EQ(MakeBackend(kind)->kind(), kind);
  if (RtlBackendAvailable()) {
    EXPECT_EQ(MakeBackend(RasterBackend::kRtl)->kind(), RasterBackend::kRtl);
  }
}

}  // namespace
}  // namespace mcpose::backends

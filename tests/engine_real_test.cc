// The engine on real YCB-Video data: level of detail (the chain shrinks monotonically, and the
// level the engine picks for a real box renders the ground-truth pose with nearly the same
// pixels and depths as the full mesh), and the raster cores' cover-rect shortcut (exactly the
// counts of a whole-box render) for every raster backend, with and without LOD; the SIMD
// backend counts exactly as the fixed-point one.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

#include "backends/backend.h"
#include "core/parallel_for.h"
#include "engine/box_scorer.h"
#include "engine/context.h"
#include "engine/initialize.h"
#include "engine/raster_cores.h"
#include "render/raster_fixed.h"
#include "mcpose/dataset.h"
#include "mcpose/estimator.h"
#include "mcpose/eval.h"
#include "render/clusters.h"
#include "render/lod.h"
#include "render/raster.h"
#include "score/box_observation.h"
#include "score/inlier.h"
#include "raster_test_util.h"
#include "test_data.h"

namespace mcpose {
namespace {

struct Rendered {
  std::vector<float> z;
  score::InlierCounts counts;
};

Rendered RenderInBox(const Mesh& mesh, const SE3& T, const Intrinsics& K, const score::BoxObservation& box) {
  render::RasterParams p;
  p.fx = K.fx, p.fy = K.fy, p.cx = K.cx, p.cy = K.cy;
  p.box = box.rect;
  std::vector<render::ScreenVertex> sv(mesh.vertices_m.size());
  render::ProjectVertices(mesh.vertices_m, T.R.cast<float>(), T.t.cast<float>(), p, sv);
  Rendered r;
  r.z.assign(static_cast<size_t>(box.rect.area()), INFINITY);
  render::RasterizeDepthReference(sv, mesh.triangles, p, r.z.data(), nullptr);
  r.counts = score::CountInliers1D(r.z, box.observed, 0.01f);
  return r;
}

TEST(LodRealData, ChainShrinksAndChosenLevelRendersLikeTheFullMesh) {
  auto ds = Dataset::Open(testing::YcbvDir());
  ASSERT_TRUE(ds.ok()) << ds.status().ToString();
  auto frame = (*ds)->LoadFrame(FrameKey{49, 1});
  ASSERT_TRUE(frame.ok()) << frame.status().ToString();
  const Intrinsics& K = frame->K;
  for (const GtInstance& gt : frame->gt) {
    auto mesh = (*ds)->LoadMesh(gt.obj_id);
    ASSERT_TRUE(mesh.ok());
    const render::LodChain chain = render::LodChain::Build(*mesh);
    ASSERT_GE(chain.num_levels(), 3) << "obj " << gt.obj_id;
    for (int l = 1; l < chain.num_levels(); ++l) {
      EXPECT_LT(chain.level(l).mesh.triangles.size(), chain.level(l - 1).mesh.triangles.size());
      EXPECT_GE(chain.level(l).error_m, chain.level(l - 1).error_m);
      EXPECT_TRUE(chain.level(l).mesh.Validate("lod").ok());
    }

    auto mask = (*ds)->LoadVisibleMask(frame->key, gt);
    ASSERT_TRUE(mask.ok());
    Detection d;
    ASSERT_GT(MaskBox(*mask, &d), 0);
    d.obj_id = gt.obj_id, d.score = 1;
    const score::BoxObservation box = score::DistributeBox(
        frame->depth, K, engine::ClipBox(d.x, d.y, d.w, d.h, K.width, K.height), 1.0, InlierMode::k1D);
    const double z = engine::InitialDepth(K, *mesh, d, box, 0.5);
    const int level = chain.Select(render::LodErrorBudgetM(1.0f, static_cast<float>(z),
                                                           static_cast<float>(std::min(K.fx, K.fy))));
    EXPECT_GT(level, 0) << "a 1-pixel budget should allow a simplified level";

    const Rendered full = RenderInBox(*mesh, gt.T_cam_obj, K, box);
    const Rendered lod = RenderInBox(chain.level(level).mesh, gt.T_cam_obj, K, box);
    int both = 0, either = 0;
    std::vector<float> dz;
    for (size_t i = 0; i < full.z.size(); ++i) {
      const bool a = std::isfinite(full.z[i]), b = std::isfinite(lod.z[i]);
      both += a && b, either += a || b;
      if (a && b) dz.push_back(std::fabs(full.z[i] - lod.z[i]));
    }
    ASSERT_FALSE(dz.empty());
    std::sort(dz.begin(), dz.end());
    const double iou = static_cast<double>(both) / either;
    const double inlier_change =
        std::fabs(lod.counts.inliers - full.counts.inliers) / std::max(1.0, double(full.counts.inliers));
    std::printf("  obj %2d: level %d of %d, %zu -> %zu triangles, error %.2f mm; IoU %.4f, "
                "median |dz| %.3f mm, p99 %.3f mm, inliers %d -> %d\n",
                gt.obj_id, level, chain.num_levels(), mesh->triangles.size(),
                chain.level(level).mesh.triangles.size(), 1000 * chain.level(level).error_m, iou,
                1000 * dz[dz.size() / 2], 1000 * dz[dz.size() * 99 / 100], full.counts.inliers,
                lod.counts.inliers);
    EXPECT_GE(iou, 0.98) << "obj " << gt.obj_id;
    EXPECT_LE(dz[dz.size() / 2], 0.001f) << "obj " << gt.obj_id;
    EXPECT_LE(inlier_change, 0.02) << "obj " << gt.obj_id;
  }
}

// One object of a real frame, boxed by its visible mask (score 1).
struct ObjectInFrame {
  std::optional<Frame> frame;
  std::optional<Mesh> mesh;
  Detection box;
};
void LoadObjectInFrame(FrameKey key, int obj_id, ObjectInFrame* out) {
  auto ds = Dataset::Open(testing::YcbvDir());
  ASSERT_TRUE(ds.ok()) << ds.status().ToString();
  auto frame = (*ds)->LoadFrame(key);
  ASSERT_TRUE(frame.ok()) << frame.status().ToString();
  auto mesh = (*ds)->LoadMesh(obj_id);
  ASSERT_TRUE(mesh.ok());
  for (const GtInstance& gt : frame->gt)
    if (gt.obj_id == obj_id) { ASSERT_GT(MaskBox(*(*ds)->LoadVisibleMask(frame->key, gt), &out->box), 0); }
  out->box.obj_id = obj_id, out->box.score = 1;
  out->frame = std::move(frame).value();
  out->mesh = std::move(mesh).value();
}

// Samples drawn as the estimator draws them for box `d` of `o` (default options otherwise).
filter::ParticleSet Samples(const ObjectInFrame& o, const Detection& d, int samples, uint64_t stream) {
  EstimatorOptions opt;
  opt.samples = samples;
  engine::Context context(opt);
  auto scorer = engine::BoxScorer::Create(context, o.frame->K, o.frame->depth, *o.mesh, std::span(&d, 1));
  EXPECT_TRUE(scorer.ok()) << scorer.status().ToString();
  filter::ParticleSet particles;
  engine::InitializeSamples(**scorer, opt, stream, &particles);
  return particles;
}

// The raster cores' input when every box renders one mesh (a LOD level), with or without its
// culling clusters.
struct LevelTargets {
  LevelTargets(const render::LodLevel& level, std::span<const score::BoxObservation> boxes, bool clusters) {
    for (const score::BoxObservation& b : boxes) targets.push_back({&b, &level.mesh, clusters ? &level.clusters : nullptr});
  }
  LevelTargets(const Mesh& mesh, std::span<const score::BoxObservation> boxes) {
    for (const score::BoxObservation& b : boxes) targets.push_back({&b, &mesh, nullptr});
  }
  void SetClusters(const render::ClusterSet* clusters) {
    for (auto& t : targets) t.clusters = clusters;
  }
  std::vector<backends::BoxTarget> targets;
  backends::SampleSettings settings;
};

TEST(RasterCoresRealData, CountsEqualAWholeBoxRenderForEveryBackendAndLod) {
  ObjectInFrame o;
  ASSERT_NO_FATAL_FAILURE(LoadObjectInFrame(FrameKey{1, 1}, 5, &o));  // 006_mustard_bottle
  const auto& frame = o.frame;
  const auto& mesh = o.mesh;
  const Intrinsics& K = frame->K;
  const Detection& d = o.box;
  std::vector<score::BoxObservation> boxes;
  boxes.push_back(score::DistributeBox(frame->depth, K, engine::ClipBox(d.x, d.y, d.w, d.h, K.width, K.height),
                                          1.0, InlierMode::k1D));
  const filter::ParticleSet particles = Samples(o, d, 200, 7);
  const render::LodChain chain = render::LodChain::Build(*mesh);

  for (RasterBackend backend :
       {RasterBackend::kScalar, RasterBackend::kFixedPoint, RasterBackend::kSimd, RasterBackend::kFloatSimd}) {
    for (int level : {0, chain.num_levels() - 1}) {
      const LevelTargets job(chain.level(level), boxes, /*clusters=*/false);
      engine::RasterCores cores(2, backend);
      std::vector<score::InlierCounts> counts(particles.size());
      RasterCounters stats;
      cores.Score(job.targets, job.settings, particles, counts, &stats);
      EXPECT_GT(stats.fragments, 0);

      // Whole-box reference: clear the box, render, count over the box.
      render::RasterParams p;
      p.fx = K.fx, p.fy = K.fy, p.cx = K.cx, p.cy = K.cy;
      p.box = boxes[0].rect;
      const Mesh& m = chain.level(level).mesh;
      std::vector<render::ScreenVertex> sv(m.vertices_m.size());
      for (size_t i = 0; i < particles.size(); ++i) {
        render::ProjectVertices(m.vertices_m, particles.R_cam_obj[i].cast<float>(),
                                particles.t_cam_obj_m[i].cast<float>(), p, sv);
        std::vector<float> z(static_cast<size_t>(p.box.area()), INFINITY);
        if (backend == RasterBackend::kScalar || backend == RasterBackend::kFloatSimd) {
          render::RasterizeDepthReference(sv, m.triangles, p, z.data(), nullptr);
        } else {
          render::RasterizeDepthFixedPoint(sv, m.triangles, p, z.data(), nullptr);
        }
        ASSERT_EQ(counts[i], score::CountInliers1D(z, boxes[0].observed, job.settings.eps_m))
            << RasterBackendName(backend) << " level " << level << " sample " << i;
      }
    }
  }
}

// Pixel stride 2: the raster cores' counts on the box's sample grid match the full-resolution
// reference render read at the grid's pixels (x0 + 2i, y0 + 2j). The grid render goes through
// other float operations (scaled coordinates), so a pixel on a triangle edge may flip: the
// counts agree to 0.5% of the rendered pixels, summed over the samples.
TEST(RasterCoresRealData, StrideTwoGridMatchesTheFullRenderAtTheGridPixels) {
  ObjectInFrame o;
  ASSERT_NO_FATAL_FAILURE(LoadObjectInFrame(FrameKey{1, 1}, 2, &o));  // 003_cracker_box
  const auto& frame = o.frame;
  const auto& mesh = o.mesh;
  const Intrinsics& K = frame->K;
  const Detection& d = o.box;
  const render::PixelRect rect = engine::ClipBox(d.x, d.y, d.w, d.h, K.width, K.height);
  std::vector<score::BoxObservation> grid, full;
  grid.push_back(score::DistributeBox(frame->depth, K, rect, 1.0, InlierMode::k1D, 2));
  full.push_back(score::DistributeBox(frame->depth, K, rect, 1.0, InlierMode::k1D, 1));
  EXPECT_EQ(grid[0].rect.width(), (rect.width() + 1) / 2);
  EXPECT_EQ(grid[0].rect.height(), (rect.height() + 1) / 2);
  for (int j = 0; j < grid[0].rect.height(); ++j)
    for (int i = 0; i < grid[0].rect.width(); ++i)
      ASSERT_EQ(grid[0].observed[j * grid[0].rect.width() + i], full[0].observed[2 * j * rect.width() + 2 * i]);
  const filter::ParticleSet particles = Samples(o, d, 100, 7);
  for (RasterBackend backend : {RasterBackend::kScalar, RasterBackend::kSimd}) {
    const LevelTargets job(*mesh, grid);
    engine::RasterCores cores(2, backend);
    std::vector<score::InlierCounts> counts(particles.size());
    cores.Score(job.targets, job.settings, particles, counts, nullptr);
    int64_t rendered = 0, diff_rendered = 0, diff_inliers = 0;
    for (size_t i = 0; i < particles.size(); ++i) {
      const Rendered r = RenderInBox(*mesh, particles.Pose(i), K, full[0]);
      score::InlierCounts sampled;
      for (int y = 0; y < rect.height(); y += 2)
        for (int x = 0; x < rect.width(); x += 2) {
          const float zr = r.z[y * rect.width() + x], zo = full[0].observed[y * rect.width() + x];
          sampled.rendered += zr != INFINITY;
          sampled.inliers += zr != INFINITY && zo > 0 && std::fabs(zr - zo) < 0.01f;
        }
      EXPECT_EQ(counts[i].observed, grid[0].n_observed);
      rendered += sampled.rendered;
      diff_rendered += std::abs(counts[i].rendered - sampled.rendered);
      diff_inliers += std::abs(counts[i].inliers - sampled.inliers);
    }
    EXPECT_GT(rendered, 0);
    EXPECT_LE(diff_rendered, 0.005 * rendered) << RasterBackendName(backend);
    EXPECT_LE(diff_inliers, 0.005 * rendered) << RasterBackendName(backend);
  }
}

// Cluster culling drops whole clusters before setup; the inlier counts must be exactly those of
// the per-triangle path, for the fixed and SIMD cores, every LOD level, at strides 1 and 2, on a
// box that shows all of the mustard bottle and one that shows part of the tomato soup can
// (3/138); and batched triangle setup must match per-triangle setup exactly, counters included.
// The cone test is not exact at the fragment level: here it drops 1 covered pixel in
// 0.5-2 million (a triangle the per-triangle path rasterized), so fragments agree to 1e-5.
TEST(RasterCoresRealData, ClusterCullingGivesTheSameCounts) {
  int64_t dropped_clusters = 0;
  for (const auto& [key, obj_id] : {std::pair{FrameKey{1, 1}, 5}, std::pair{FrameKey{3, 138}, 4}}) {
    ObjectInFrame o;
    ASSERT_NO_FATAL_FAILURE(LoadObjectInFrame(key, obj_id, &o));
    const Intrinsics& K = o.frame->K;
    const Detection& d = o.box;
    for (int stride : {1, 2}) {
      std::vector<score::BoxObservation> boxes;
      boxes.push_back(score::DistributeBox(o.frame->depth, K, engine::ClipBox(d.x, d.y, d.w, d.h, K.width, K.height),
                                              1.0, InlierMode::k1D, stride));
      const filter::ParticleSet particles = Samples(o, d, 300, 11);
      const render::LodChain chain = render::LodChain::Build(*o.mesh);
      for (RasterBackend backend : {RasterBackend::kFixedPoint, RasterBackend::kSimd}) {
        for (int level = 0; level < chain.num_levels(); ++level) {
          LevelTargets job(chain.level(level), boxes, /*clusters=*/false);
          engine::RasterCores cores(2, backend);
          std::vector<score::InlierCounts> plain(particles.size()), clustered(particles.size());
          RasterCounters plain_stats, clustered_stats;
          cores.Score(job.targets, job.settings, particles, plain, &plain_stats);
          job.SetClusters(&chain.level(level).clusters);
          cores.Score(job.targets, job.settings, particles, clustered, &clustered_stats);
          EXPECT_EQ(clustered, plain) << "obj " << obj_id << " stride " << stride << " level " << level;
          EXPECT_GT(clustered_stats.clusters, 0);
          EXPECT_LE(std::abs(clustered_stats.fragments - plain_stats.fragments), 1e-5 * plain_stats.fragments);
          EXPECT_LE(clustered_stats.fragments, plain_stats.fragments);
          EXPECT_EQ(clustered_stats.triangles_in, plain_stats.triangles_in);
          dropped_clusters += clustered_stats.clusters_culled_backface + clustered_stats.clusters_culled_outside_box;
          // Batched setup (the default above) against the per-triangle setup: identical.
          job.settings.batched_setup = false;
          std::vector<score::InlierCounts> per_triangle(particles.size());
          RasterCounters per_triangle_stats;
          cores.Score(job.targets, job.settings, particles, per_triangle, &per_triangle_stats);
          EXPECT_EQ(per_triangle, clustered) << "obj " << obj_id << " stride " << stride << " level " << level;
          EXPECT_EQ(per_triangle_stats, clustered_stats) << "obj " << obj_id << " level " << level;
          // Back faces rasterized: only clusters outside the box are dropped (exact), so the
          // same counts and fragments as the per-triangle path.
          if (level + 1 == chain.num_levels()) {
            job.settings.batched_setup = true, job.settings.cull_backfaces = false;
            std::vector<score::InlierCounts> both_plain(particles.size()), both_clustered(particles.size());
            RasterCounters both_plain_stats, both_clustered_stats;
            cores.Score(job.targets, job.settings, particles, both_clustered, &both_clustered_stats);
            job.SetClusters(nullptr);
            cores.Score(job.targets, job.settings, particles, both_plain, &both_plain_stats);
            EXPECT_EQ(both_clustered, both_plain) << "obj " << obj_id << " stride " << stride;
            EXPECT_EQ(both_clustered_stats.clusters_culled_backface, 0);
            EXPECT_EQ(both_clustered_stats.culled_backface, 0);
            EXPECT_GT(both_clustered_stats.triangles_rasterized, plain_stats.triangles_rasterized);
            EXPECT_EQ(both_clustered_stats.fragments, both_plain_stats.fragments);
          }
        }
      }
    }
  }
  EXPECT_GT(dropped_clusters, 1000);
}

// The LOD budget is in image pixels at any pixel stride: the mustard bottle (1/1) gets the same
// level at strides 1, 2 and 3, its deviation is within the budget, and the next coarser level's
// is not (a coarser scoring grid does not make a coarser mesh safe: docs/engine-notes.md).
TEST(LodRealData, LevelIsChosenInImagePixelsAtAnyStride) {
  ObjectInFrame o;
  ASSERT_NO_FATAL_FAILURE(LoadObjectInFrame(FrameKey{1, 1}, 5, &o));
  const Intrinsics& K = o.frame->K;
  const render::LodChain chain = render::LodChain::Build(*o.mesh);
  const Detection& d = o.box;
  EstimatorOptions opt;
  int first = -1;
  for (int stride : {1, 2, 3}) {
    const score::BoxObservation box = score::DistributeBox(
        o.frame->depth, K, engine::ClipBox(d.x, d.y, d.w, d.h, K.width, K.height), 1.0, InlierMode::k1D, stride);
    const int level = engine::SelectLodLevel(chain, K, *o.mesh, d, box, opt);
    if (first < 0) first = level;
    EXPECT_EQ(level, first) << "stride " << stride;
    const double z = engine::InitialDepth(K, *o.mesh, d, box, opt.init.depth_quantile);
    const double budget_m = opt.engine.lod_error_px * z / std::min(K.fx, K.fy);
    EXPECT_GT(level, 0);
    EXPECT_LE(chain.level(level).error_m, budget_m);
    if (level + 1 < chain.num_levels()) { EXPECT_GT(chain.level(level + 1).error_m, budget_m); }
  }
}

// Narrow boxes, as a detector gives for a far or mostly hidden object: strips 1 to 20 pixels
// wide across the mustard bottle (1/1), at strides 1 and 2, with the engine's LOD level and
// clusters. The SIMD core counts exactly as the fixed-point one (a grid narrower than a block
// of rows once lost depth writes on AVX2 and AVX-512).
TEST(RasterCoresRealData, NarrowBoxesCountAsTheFixedPointCore) {
  ObjectInFrame o;
  ASSERT_NO_FATAL_FAILURE(LoadObjectInFrame(FrameKey{1, 1}, 5, &o));
  const Intrinsics& K = o.frame->K;
  const render::LodChain chain = render::LodChain::Build(*o.mesh);
  int64_t fragments = 0;
  for (int stride : {1, 2}) {
    for (int width = 1; width <= 20; ++width) {
      Detection d = o.box;
      d.x += 0.5 * (d.w - width), d.w = width;  // a strip through the middle of the object
      std::vector<score::BoxObservation> boxes;
      boxes.push_back(score::DistributeBox(o.frame->depth, K,
                                              engine::ClipBox(d.x, d.y, d.w, d.h, K.width, K.height), 1.0,
                                              InlierMode::k1D, stride));
      const filter::ParticleSet particles = Samples(o, d, 100, 13);
      const int level = engine::SelectLodLevel(chain, K, *o.mesh, d, boxes[0], EstimatorOptions{});
      const LevelTargets job(chain.level(level), boxes, /*clusters=*/true);
      std::vector<score::InlierCounts> fixed(particles.size()), simd(particles.size());
      RasterCounters fixed_stats, simd_stats;
      engine::RasterCores(1, RasterBackend::kFixedPoint).Score(job.targets, job.settings, particles, fixed, &fixed_stats);
      engine::RasterCores(2, RasterBackend::kSimd).Score(job.targets, job.settings, particles, simd, &simd_stats);
      ASSERT_EQ(simd, fixed) << "stride " << stride << " width " << width;
      EXPECT_EQ(simd_stats, fixed_stats) << "stride " << stride << " width " << width;
      fragments += simd_stats.fragments;
    }
  }
  EXPECT_GT(fragments, 100000);
}

// Boxes are clipped to the image and rounded outwards; any finite box, however far outside,
// gives a rect inside the image or an empty one, and a non-finite one an empty one.
TEST(RasterCores, ClipBoxKeepsEveryBoxInsideTheImage) {
  const auto same = [](render::PixelRect a, render::PixelRect b) {
    return a.x0 == b.x0 && a.y0 == b.y0 && a.x1 == b.x1 && a.y1 == b.y1;
  };
  EXPECT_TRUE(same(engine::ClipBox(10.5, 20, 5, 0.2, 640, 480), render::PixelRect{10, 20, 16, 21}));
  EXPECT_TRUE(same(engine::ClipBox(-30, -40, 100, 1e9, 640, 480), render::PixelRect{0, 0, 70, 480}));
  EXPECT_TRUE(same(engine::ClipBox(630, 0, 1e300, 10, 640, 480), render::PixelRect{630, 0, 640, 10}));
  EXPECT_TRUE(engine::ClipBox(1e300, 10, 20, 20, 640, 480).empty());
  EXPECT_TRUE(engine::ClipBox(-1e300, 10, 20, 20, 640, 480).empty());
  EXPECT_TRUE(engine::ClipBox(10, -1e300, 20, 1e300, 640, 480).empty());  // ends at 0
  EXPECT_TRUE(engine::ClipBox(640, 10, 20, 20, 640, 480).empty());
  EXPECT_TRUE(engine::ClipBox(10, 10, NAN, 20, 640, 480).empty());
  EXPECT_TRUE(engine::ClipBox(INFINITY, 10, 20, 20, 640, 480).empty());
}

TEST(RasterCores, BoxStrideKeepsTheGridWithinItsBudget) {
  EngineOptions o;
  o.pixel_stride = 2;
  o.max_grid_pixels = 6000;
  EXPECT_EQ(engine::BoxStride(render::PixelRect{0, 0, 100, 100}, o), 2);  // 2 500 grid pixels
  EXPECT_EQ(engine::BoxStride(render::PixelRect{0, 0, 200, 200}, o), 3);  // 10 000 at 2, 4 489 at 3
  EXPECT_EQ(engine::BoxStride(render::PixelRect{10, 20, 650, 500}, o), 8);  // 640 x 480: 4 800 at 8
  o.max_grid_pixels = 0;
  EXPECT_EQ(engine::BoxStride(render::PixelRect{0, 0, 640, 480}, o), 2);
  o.pixel_stride = 1;
  o.max_grid_pixels = 1;
  EXPECT_EQ(engine::BoxStride(render::PixelRect{0, 0, 640, 480}, o), 16);  // the largest stride
}

TEST(Lod, SelectPicksTheCoarsestLevelWithinBudget) {
  Mesh m;
  // A finely tessellated unit square (flat: simplifies to very few triangles at zero error).
  const int n = 40;
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) m.vertices_m.emplace_back(x / float(n), y / float(n), 0.f);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const uint32_t a = y * (n + 1) + x, b = a + 1, c = a + n + 1, d = c + 1;
      m.triangles.push_back({a, b, d});
      m.triangles.push_back({a, d, c});
    }
  const render::LodChain chain = render::LodChain::Build(m);
  ASSERT_GE(chain.num_levels(), 2);
  for (float budget : {0.f, 1e-6f, 1e-4f, 1e-2f}) {
    const int l = chain.Select(budget);
    if (l > 0) { EXPECT_LE(chain.level(l).error_m, budget); }
    if (l + 1 < chain.num_levels()) { EXPECT_GT(chain.level(l + 1).error_m, budget); }
  }
  EXPECT_EQ(chain.Select(-1.f), 0);
  EXPECT_EQ(chain.Select(1e9f), chain.num_levels() - 1);
  EXPECT_EQ(render::LodErrorBudgetM(0.f, 1.f, 1000.f), 0.f);
  EXPECT_FLOAT_EQ(render::LodErrorBudgetM(2.f, 0.5f, 1000.f), 0.001f);
  EXPECT_NE(render::MeshFingerprint(m), render::MeshFingerprint(chain.level(chain.num_levels() - 1).mesh));
}

}  // namespace
}  // namespace mcpose

namespace mcpose {
namespace {

// Estimator::PrepareMeshes builds the LOD chains of several real meshes at once (one per raster
// core); estimates afterwards equal those of an estimator that built each chain on first use.
TEST(EstimatorRealData, PreparedMeshesGiveTheSameEstimates) {
  ObjectInFrame mustard, banana;
  LoadObjectInFrame(FrameKey{2, 1}, 5, &mustard);
  LoadObjectInFrame(FrameKey{2, 1}, 10, &banana);
  ASSERT_TRUE(mustard.mesh && banana.mesh);
  EstimatorOptions opt;
  opt.samples = 96;
  opt.max_iterations = 4;
  opt.engine.threads = 2;
  auto prepared = std::move(Estimator::Create(opt)).value();
  auto lazy = std::move(Estimator::Create(opt)).value();
  const Mesh* meshes[] = {&*mustard.mesh, &*banana.mesh, &*mustard.mesh};  // a repeat is built once
  prepared->PrepareMeshes(meshes);
  for (const ObjectInFrame* o : {&mustard, &banana}) {
    const std::vector<Detection> boxes = {o->box};
    auto a = prepared->Estimate(o->frame->K, o->frame->depth, *o->mesh, boxes, 7);
    auto b = lazy->Estimate(o->frame->K, o->frame->depth, *o->mesh, boxes, 7);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(a->box_triangles, b->box_triangles);
    EXPECT_LT(a->box_triangles[0], static_cast<int>(o->mesh->triangles.size()));  // a coarser level
    EXPECT_EQ(a->T_cam_obj.R, b->T_cam_obj.R);
    EXPECT_EQ(a->T_cam_obj.t, b->T_cam_obj.t);
    ASSERT_EQ(a->iterations.size(), b->iterations.size());
    for (size_t i = 0; i < a->iterations.size(); ++i)
      EXPECT_EQ(a->iterations[i].mean_weight, b->iterations[i].mean_weight);
  }
}

}  // namespace
}  // namespace mcpose

// Raster cores: the engine boundary between the filter and the renderers. A batch of pose
// hypotheses goes in, one InlierCounts per hypothesis comes out. Each worker thread of the
// pool is one raster core with its own scratch (projected vertices, box z-buffer).
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "core/parallel_for.h"
#include "filter/particles.h"
#include "mcpose/camera.h"
#include "mcpose/image.h"
#include "mcpose/mesh.h"
#include "mcpose/options.h"
#include "render/clusters.h"
#include "render/raster_fixed.h"
#include "render/raster.h"
#include "score/inlier.h"

namespace mcpose::engine {

// One box's observed depth, cut out of the frame once by the depth distributor and shared by
// every core and every iteration.
//
// Pixel stride s: the box is scored on a grid of every s-th image pixel in x and y, starting at
// its top-left pixel. The raster cores render into that grid as into a smaller image, through
// `K_grid`, whose pixel (x0 + i, y0 + j) is centred on image pixel (x0 + s i, y0 + s j): the
// same rays, s^2 times fewer of them. At s = 1, rect = image_rect and K_grid = the camera.
struct BoxDepth {
  render::PixelRect rect;        // the raster rect, grid pixels
  render::PixelRect image_rect;  // the box in image pixels
  int stride = 1;
  Intrinsics K_grid;             // projection onto the grid (fx / s, fy / s, shifted centre)
  std::vector<float> observed;         // rect-sized, metres, 0 = invalid
  std::vector<float> observed_or_nan;  // the same with NaN where invalid (the SIMD counter)
  int32_t n_observed = 0;              // N_b
  double score = 0;                    // detector confidence
  std::unique_ptr<score::ObservedCloud> cloud;  // only for InlierMode::k3D
};

// Clips a detection box [x, x + w) x [y, y + h) to the image and rounds it outwards to whole
// pixels. Returns an empty rect if nothing of it lies in the image.
render::PixelRect ClipBox(double x, double y, double w, double h, int width, int height);

// Builds the BoxDepth of `rect` (image pixels, inside the image) at pixel stride `stride` >= 1.
BoxDepth DistributeDepth(const DepthImage& depth, const Intrinsics& K, const render::PixelRect& rect,
                         double score, InlierMode mode, int stride = 1);

// The pixel stride of a box: options.pixel_stride, or the smallest larger one whose grid holds
// at most options.max_grid_pixels pixels (when that is > 0).
int BoxStride(const render::PixelRect& rect, const EstimatorOptions& options);

// Distinct image pixels read by the depth distributor for these boxes: the union of their
// sample grids (at stride 1, the union of their rects).
int64_t UnionSamples(std::span<const BoxDepth* const> boxes);

struct ScoreJob {
  const Mesh* mesh = nullptr;            // the full mesh
  std::span<const Mesh* const> box_mesh; // optional: the mesh (LOD level) each box renders
  // Optional, with box_mesh: the culling clusters of each box's mesh. The fixed-point cores
  // (fixed, simd) then drop whole clusters outside the box or facing away (the same inlier
  // counts in the tests; render/clusters.h says where the cone test is not exact); the float
  // cores (scalar, float-simd) always walk every triangle.
  std::span<const render::ClusterSet* const> box_clusters;
  Intrinsics K;                          // the camera (each box renders through its K_grid)
  std::span<const BoxDepth> boxes;
  InlierMode inlier_mode = InlierMode::k1D;
  float eps_m = 0.01f;
  bool cull_backfaces = true;
  // Fixed-point and SIMD cores: snap each sample's vertices once, classify and set up its
  // triangles a vector at a time (render/setup_simd.cc); the same results as one at a time.
  bool batched_setup = true;
};

// The job's per-pixel and per-triangle settings from the options (inlier test, eps, back-face
// culling, batched setup): one place, so the estimator and the benchmark score alike.
void SetEngineOptions(const EstimatorOptions& options, ScoreJob* job);

class RasterCores {
 public:
  RasterCores(int threads, RasterBackend backend);
  ~RasterCores();

  int threads() const { return pool_.size(); }
  ThreadPool& pool() { return pool_; }

  // counts[i] = the inlier counts of particle i rendered in its box. Adds raster statistics.
  void Score(const ScoreJob& job, const filter::ParticleSet& particles,
             std::span<score::InlierCounts> counts, render::RasterStats* stats);

 private:
  struct Scratch {
    std::vector<render::ScreenVertex> vertices;
    std::vector<float> zbuf;
    render::SnappedVertices snapped;
    std::vector<render::ClusterCull> culls;  // per cluster of the sample's mesh
    std::vector<std::array<uint32_t, 3>> kept_triangles;  // the kept clusters' triangles
    render::RasterStats stats;
  };
  ThreadPool pool_;
  RasterBackend backend_;
  std::vector<Scratch> scratch_;
};

}  // namespace mcpose::engine

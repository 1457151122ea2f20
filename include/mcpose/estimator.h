// The Monte-Carlo pose estimator: one object class of one image at a time.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "mcpose/camera.h"
#include "mcpose/detection.h"
#include "mcpose/image.h"
#include "mcpose/mesh.h"
#include "mcpose/options.h"
#include "mcpose/se3.h"
#include "mcpose/status.h"

namespace mcpose {

// Engine counters of one object's run, summed over iterations.
struct EngineCounters {
  int64_t triangles_full = 0;          // triangles of the full mesh, per sample render
  int64_t triangles_in = 0;            // triangles submitted (after the LOD choice)
  int64_t culled_backface = 0;
  int64_t culled_degenerate = 0;
  int64_t culled_outside_box = 0;      // bounding box misses the sample's box
  int64_t culled_near = 0;             // a vertex behind the near plane
  int64_t culled_between_pixels = 0;   // covers no pixel centre
  int64_t triangles_rasterized = 0;    // covered at least one pixel centre
  int64_t fragments = 0;               // pixel centres covered (before the depth test)
  int64_t clusters = 0;                // culling clusters tested (cluster_culling)
  int64_t clusters_culled_backface = 0;    // dropped whole: facing away
  int64_t clusters_culled_outside_box = 0; // dropped whole: outside the box
  int64_t cdf_draws = 0;
  int64_t cdf_reads = 0;               // CDF entries read with the coarse table + fine search
  int64_t cdf_reads_naive = 0;         // entries a linear search from the start would read
  int64_t depth_bytes_read = 0;        // observed depth bytes read by the depth distributor
  int64_t depth_bytes_read_naive = 0;  // bytes a per-sample copy of the box would read
};

struct ObjectEstimate {
  int obj_id = 0;
  SE3 T_cam_obj;                  // the best-weighted sample ever seen
  double best_weight = 0;
  double final_mean_weight = 0;
  int iterations = 0;             // iterations run (scored generations)
  int best_box = -1;              // index into the boxes passed in
  std::vector<double> mean_weight_history;  // one entry per iteration
  std::vector<int> box_triangles;  // triangles of the mesh (LOD level) each box renders
  // Wall time of each iteration: render + inlier counting (the raster cores), and the whole
  // iteration (raster cores + weights + resampling + diffusion), milliseconds.
  std::vector<double> score_ms, iteration_ms;
  // Per iteration: fragments rasterized and observed-depth bytes the distributor read.
  std::vector<int64_t> fragments_per_iteration, depth_bytes_per_iteration;
  EngineCounters counters;
};

class Estimator {
 public:
  // Fails if the options are invalid (the message names the field).
  static StatusOr<std::unique_ptr<Estimator>> Create(const EstimatorOptions& options);
  ~Estimator();

  // Estimates the pose of one object class from all its boxes in one image. Boxes must lie at
  // least partly inside the image and have positive size; a box is clipped to the image.
  // `stream_id` selects independent random streams (e.g. a hash of image and class), so the
  // result depends on (seed, stream_id) only, never on the thread count.
  StatusOr<ObjectEstimate> Estimate(const Intrinsics& K, const DepthImage& depth, const Mesh& mesh,
                                    std::span<const Detection> boxes, uint64_t stream_id);

  // Builds the level-of-detail chains (and their culling clusters) of these meshes now, one
  // mesh per raster core, instead of one at a time on their first Estimate. Optional: the
  // results are the same either way. Nothing to do without LOD (lod_error_px 0).
  void PrepareMeshes(std::span<const Mesh* const> meshes);

  const EstimatorOptions& options() const;

 private:
  struct Impl;
  explicit Estimator(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace mcpose

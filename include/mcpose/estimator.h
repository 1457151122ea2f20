// The Monte-Carlo pose estimator: one object class of one image at a time.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "mcpose/camera.h"
#include "mcpose/counters.h"
#include "mcpose/detection.h"
#include "mcpose/image.h"
#include "mcpose/mesh.h"
#include "mcpose/options.h"
#include "mcpose/se3.h"
#include "mcpose/status.h"

namespace mcpose {

// One iteration of the filter (one scored generation of samples).
struct IterationSummary {
  double mean_weight = 0;   // of this generation
  double best_weight = 0;   // of this generation
  double score_ms = 0;      // render + inlier counting on the raster cores, wall time
  double iteration_ms = 0;  // the whole iteration: scoring, weights, resampling, diffusion
  EngineCounters counters;  // this iteration's
};

// Twin resolution's record (AppearanceOptions::resolve_twins).
struct TwinRecord {
  bool ran = false;
  int candidates = 0;        // poses scored at full resolution
  int winner = 0;            // the one kept; 0 = the filter's own answer
  double winner_weight = 0;  // its full-resolution weight
  double margin = 0;         // its weight minus the best other candidate's
  int refine_iterations = 0;
  double ms = 0;             // wall time of scoring and refinement
};

// Refinement's record (RefineOptions).
struct RefineRecord {
  bool ran = false;
  bool accepted = false;        // the aligned pose did not lower the full-resolution weight
  int iterations = 0;           // Gauss-Newton steps taken
  int pairs = 0;                // model-observed pairs of the last step
  double rms_before_m = 0, rms_after_m = 0;      // robust point-to-plane residual
  double weight_before = 0, weight_after = 0;    // full-resolution weight
  double ms = 0;                // wall time
};

struct ObjectEstimate {
  int obj_id = 0;
  SE3 T_cam_obj;          // the best-weighted sample ever seen
  double best_weight = 0;
  int best_box = -1;      // index into the boxes passed in
  std::vector<IterationSummary> iterations;  // one per scored generation, in order
  std::vector<int> box_triangles;  // triangles of the mesh (LOD level) each box renders
  int64_t depth_pixels_read = 0;   // observed depth pixels the depth distributor cut out
  bool colour = false;             // whether the weight had its colour term
  TwinRecord twins;
  RefineRecord refine;

  double final_mean_weight() const { return iterations.empty() ? 0 : iterations.back().mean_weight; }
  EngineCounters Totals() const;  // the counters summed over the iterations
};

namespace engine {
class Context;
}

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
  // The same with the frame's colour image (registered to the depth image, same size): the
  // weight has its colour term when the mesh has colour and options().appearance allows it.
  StatusOr<ObjectEstimate> Estimate(const Intrinsics& K, const DepthImage& depth, const ColourImage* colour,
                                    const Mesh& mesh, std::span<const Detection> boxes, uint64_t stream_id);

  // Builds the level-of-detail chains (and their culling clusters) of these meshes now, one
  // mesh per raster core, instead of one at a time on their first Estimate. Optional: the
  // results are the same either way. Nothing to do without LOD (lod_error_px 0).
  void PrepareMeshes(std::span<const Mesh* const> meshes);

  const EstimatorOptions& options() const;

 private:
  explicit Estimator(std::unique_ptr<engine::Context> context);
  std::unique_ptr<engine::Context> context_;
};

}  // namespace mcpose

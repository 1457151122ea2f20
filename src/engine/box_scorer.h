// The scoring seam: everything between one object class's boxes in one image and the weight of
// a pose hypothesis. Built once per estimate, it clips and checks the boxes, cuts out their
// observed depth (the depth distributor), picks each box's mesh level and culling clusters, and
// then renders, counts and weighs batches of samples on the context's raster cores. The
// estimator, `mcpose bench` and the diagnostics all score through it.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "backends/backend.h"
#include "engine/context.h"
#include "filter/particles.h"
#include "mcpose/camera.h"
#include "mcpose/detection.h"
#include "mcpose/estimator.h"
#include "mcpose/image.h"
#include "mcpose/mesh.h"
#include "mcpose/status.h"
#include "render/lod.h"
#include "score/box_fit.h"
#include "score/box_observation.h"

namespace mcpose::engine {

// Clips a detection box [x, x + w) x [y, y + h) to the image and rounds it outwards to whole
// pixels. Returns an empty rect if nothing of it lies in the image.
render::PixelRect ClipBox(double x, double y, double w, double h, int width, int height);
// The pixel stride of a box: options.pixel_stride, or the smallest larger one whose grid holds
// at most options.max_grid_pixels pixels (when that is > 0).
int BoxStride(const render::PixelRect& rect, const EngineOptions& options);

// How finely a scorer renders: as the engine options say, or every pixel of the full mesh.
enum class Resolution { kEngine, kFull };

class BoxScorer {
 public:
  // Checks the inputs (intrinsics, depth and colour sizes, mesh, boxes: all of one class, each
  // per CheckBox) and prepares every box. The colour term is used when `colour` is given, the
  // mesh has colour and the options allow it. kFull renders every pixel of every box with the
  // full mesh (on the same raster cores), for a few poses that must be told apart finely.
  // Errors name the box.
  static StatusOr<std::unique_ptr<BoxScorer>> Create(Context& context, const Intrinsics& K,
                                                     const DepthImage& depth, const Mesh& mesh,
                                                     std::span<const Detection> boxes,
                                                     const ColourImage* colour = nullptr,
                                                     Resolution resolution = Resolution::kEngine);
  BoxScorer(const BoxScorer&) = delete;
  BoxScorer& operator=(const BoxScorer&) = delete;

  const Intrinsics& K() const { return K_; }
  const Mesh& mesh() const { return *mesh_; }
  const DepthImage& depth() const { return *depth_; }
  // The mesh's rest poses for the initialization (Context::Rests), or null.
  const MeshRests* rests() const { return rests_.get(); }
  int obj_id() const { return detections_.front().obj_id; }
  int num_boxes() const { return static_cast<int>(detections_.size()); }
  const Detection& detection(int b) const { return detections_[static_cast<size_t>(b)]; }
  const score::BoxObservation& box_observation(int b) const { return observed_[static_cast<size_t>(b)]; }
  // The mesh box b renders (its LOD level, or the full mesh) and that level (null without LOD).
  const Mesh& box_mesh(int b) const { return *targets_[static_cast<size_t>(b)].mesh; }
  const render::LodLevel* box_level(int b) const { return levels_[static_cast<size_t>(b)]; }
  // Observed depth pixels cut out for all boxes: the union of their sample grids.
  int64_t depth_pixels_read() const;
  // Whether the weight has its colour term (the model's colour grid, or null).
  bool uses_colour() const { return colour_ != nullptr; }
  const appearance::ColourGrid* colour_grid() const { return colour_.get(); }

  // Steps 2 and 3 of the filter: counts[i] = the inlier counts of particle i rendered in its
  // box, then particles->weight[i] its weight, whose colour term (when the scorer uses
  // colour) has weight `colour_weight`, the options' appearance.weight when negative. Add the
  // engine's counters to *counters.
  void Count(const filter::ParticleSet& particles, std::span<score::InlierCounts> counts, EngineCounters* counters);
  void Weigh(filter::ParticleSet* particles, EngineCounters* counters, double colour_weight = -1);
  // The inlier threshold Count and Weigh use (the options' weight.eps_m until set).
  float inlier_threshold() const { return settings_.eps_m; }
  // Sets eps (and, for the hw backend, each box's depth bounds, which hold it).
  void set_inlier_threshold(float eps_m);
  // The counts of the particles of the last Weigh, in their order.
  std::span<const score::InlierCounts> last_counts() const { return counts_; }

 private:
  explicit BoxScorer(Context& context) : context_(&context) {}

  Context* context_;
  Intrinsics K_;
  const Mesh* mesh_ = nullptr;
  const DepthImage* depth_ = nullptr;
  std::vector<Detection> detections_;
  std::vector<score::BoxObservation> observed_;
  std::shared_ptr<const render::LodChain> lod_;
  std::vector<const render::LodLevel*> levels_;
  std::vector<backends::BoxTarget> targets_;
  // The meshes of targets_ in the hardware's formats (engine backend hw), one per distinct mesh.
  std::vector<std::pair<const Mesh*, std::unique_ptr<const std::vector<hw::ModelVertex>>>> hw_models_;
  backends::SampleSettings settings_;
  std::shared_ptr<const appearance::ColourGrid> colour_;
  score::ColourLookup colour_lookup_;
  std::vector<score::InlierCounts> counts_;  // Weigh's
  std::shared_ptr<const std::vector<Eigen::Vector3d>> extremes_;  // the box fit's (Context::Extremes)
  std::vector<score::FitBox> fit_boxes_;     // each box, for the box fit
  std::shared_ptr<const MeshRests> rests_;   // Context::Rests
};

}  // namespace mcpose::engine

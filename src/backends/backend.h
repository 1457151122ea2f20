// A raster-core backend renders one pose hypothesis of a mesh inside its box and counts the
// depth inliers: project -> rasterize -> count. One file per backend, beside this one:
//   scalar_reference.cc   float edge functions per pixel: the oracle every other is tested against
//   float_simd.cc         the reference a Highway vector at a time (bit-identical)
//   fixed_point.cc        vertices snapped to 1/16 pixel, integer edge functions
//   fixed_point_simd.cc   the fixed-point core a Highway vector at a time (bit-identical)
//   hardware.cc           the paper's raster core in the hardware's integer numerics (hw/)
//   rtl.cc                that core's RTL, simulated by Verilator (built where Verilator is found)
// The engine (engine/raster_cores.h) chooses one per estimate and calls it for every sample on
// every raster core; adding a backend means one file and a line in registry.cc.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "mcpose/mesh.h"
#include "mcpose/options.h"
#include "hw/raster_core.h"
#include "render/clusters.h"
#include "render/raster.h"
#include "render/raster_fixed.h"
#include "score/box_observation.h"
#include "score/inlier.h"

namespace mcpose::hw {
class RtlCore;
}

namespace mcpose::backends {

// One box as every sample rendered in it sees it: its observation, the mesh (LOD level) it
// renders and, optionally, that mesh's culling clusters and the model's colour grid (then the
// box's observation has colour too, and each sample's colour test runs after its depth count).
struct BoxTarget {
  const score::BoxObservation* observed = nullptr;
  const Mesh* mesh = nullptr;
  const render::ClusterSet* clusters = nullptr;  // null: walk every triangle
  const score::ColourLookup* colour = nullptr;   // null: depth only
  // `mesh` in the hardware's formats (hw::QuantizeModel): needed by the hw backend only.
  const std::vector<hw::ModelVertex>* hw_model = nullptr;
};

// Settings of a whole batch (from EstimatorOptions).
struct SampleSettings {
  InlierMode inlier_mode = InlierMode::k1D;
  float eps_m = 0.01f;
  bool cull_backfaces = true;
  bool batched_setup = true;  // fixed-point backends only
  int colour_step = 1;        // the colour test reads every colour_step-th pixel (score/colour.h)
};

// One raster core's working memory, reused from sample to sample.
struct Scratch {
  std::vector<render::ScreenVertex> vertices;
  std::vector<float> zbuf;  // box-sized z-buffer with kSimdPadFloats of slack
  render::SnappedVertices snapped;
  std::vector<render::ClusterCull> culls;
  std::vector<std::array<uint32_t, 3>> kept_triangles;
  // The hardware model's (hardware.cc): the vertices, the IZ z-buffer.
  std::vector<hw::Vertex> hw_vertices;
  std::vector<uint32_t> hw_zbuf;
  // The simulated RTL core of this raster core (rtl.cc).
  std::shared_ptr<hw::RtlCore> rtl_core;
};

class Backend {
 public:
  virtual ~Backend() = default;
  virtual RasterBackend kind() const = 0;
  // Renders the mesh of `box` at X_cam = R X + t into the box's z-buffer (scratch->zbuf,
  // box.observed->rect sized) and counts the inliers against its observed depth. Adds to *stats.
  virtual score::InlierCounts ScoreSample(const BoxTarget& box, const Eigen::Matrix3f& R, const Eigen::Vector3f& t,
                                          const SampleSettings& settings, Scratch* scratch,
                                          RasterCounters* stats) const = 0;
};

// The backend of `kind` (registry.cc).
std::unique_ptr<Backend> MakeBackend(RasterBackend kind);

// Steps every backend shares (backend.cc).
namespace steps {

// Sizes the scratch for `box`; returns the vertex buffer for its mesh.
std::span<render::ScreenVertex> Prepare(const BoxTarget& box, Scratch* scratch);
// `cover` (image-grid pixels, inside the box) relative to the box corner; the whole box for the
// 3-D test, which reads every pixel.
render::PixelRect RelativeCover(const score::BoxObservation& box, const render::PixelRect& cover, InlierMode mode);
// Sets the z-buffer to +infinity inside `rel`, a pixel or a SIMD vector at a time.
void ClearScalar(float* zbuf, int stride, const render::PixelRect& rel);
// The inlier counts of the rendered z-buffer, reading only `rel` for the 1-D test (SIMD or
// scalar counter: the same counts) and the whole box for the 3-D test; then, with a colour
// grid, the colour test of the depth inliers (score/colour.h) of the pose R, t.
score::InlierCounts Count(const BoxTarget& box, const float* zbuf, const render::PixelRect& rel,
                          const Eigen::Matrix3f& R, const Eigen::Vector3f& t, const SampleSettings& settings,
                          bool simd);
// The colour test of Count alone (box.colour must be set): the colour of the depth inliers of
// the pose R, t rendered into zbuf.
score::ColourStats CountColour(const BoxTarget& box, const float* zbuf, const render::PixelRect& rel,
                               const Eigen::Matrix3f& R, const Eigen::Vector3f& t, const SampleSettings& settings,
                               bool simd);
// The hardware's backends (hw and rtl): checks what the engine guarantees them (1-D inliers, the
// box's bounds, the model in the core's formats) and returns the box's area.
size_t CheckHardwareInputs(const BoxTarget& box, const SampleSettings& settings);
// The core's counts as the estimator's, with the box's N_b.
score::InlierCounts HardwareCounts(const hw::Counts& c, const score::BoxObservation& box);
// The colour test beside the hardware's core (hw and rtl): its IZ z-buffer (box-sized) in metres
// into scratch->zbuf, then CountColour over the whole box into counts->colour.
void CountHardwareColour(const BoxTarget& box, std::span<const uint32_t> hw_zbuf, const Eigen::Matrix3f& R,
                         const Eigen::Vector3f& t, const SampleSettings& settings, Scratch* scratch,
                         score::InlierCounts* counts);

}  // namespace steps

}  // namespace mcpose::backends

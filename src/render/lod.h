// Level of detail for the raster cores: a chain of meshoptimizer simplifications of one mesh,
// each with its measured geometric deviation from the full mesh in metres. The engine picks, per
// box, the coarsest level whose deviation, projected at the box's depth, stays under a pixel
// budget (engine::SelectLodLevel), so a far or small object is rendered with far fewer
// triangles than its full mesh.
#pragma once

#include <cstdint>
#include <vector>

#include "mcpose/mesh.h"
#include "render/clusters.h"

namespace mcpose::render {

struct LodLevel {
  Mesh mesh;             // vertices compacted to those the triangles use
  // The level's deviation from the full mesh, metres: the larger of the measured one
  // (DeviationMeter, render/surface_distance.h) and meshoptimizer's reported error, and never
  // below the previous level's. Level selection compares this with the pixel budget. Measured
  // on meshoptimizer's vertices (LodVertices::kKept) in either placement, so both placements
  // draw the same levels.
  float error_m = 0;
  float meshopt_error_m = 0;  // meshoptimizer's reported (quadric) error alone, metres
  ClusterSet clusters;   // the same triangles in culling clusters (render/clusters.h)
};

// Where a level's vertices lie. meshoptimizer keeps a subset of the full mesh's vertices, so a
// level's triangles are chords of the full surface: inside it wherever it bulges, on average
// (on the YCB-Video meshes the cracker box's 310-triangle level lies 0.19 mm inside, the
// mustard bottle's 486-triangle one 0.20 mm; docs/engine-notes.md). kUnbiased then moves each
// vertex along its normal, kUnbiasRounds times, by the area-weighted mean signed offset of the
// full surface from the level triangles around it (SurfaceOffsets, render/surface_distance.h;
// about kUnbiasSamplesPerTriangle samples of the full surface per level triangle), which takes
// the mean signed offset to about zero and the mean distance down by a third or more (the
// cracker box's 310 triangles: 0.29 -> 0.18 mm).
enum class LodVertices {
  kKept,      // meshoptimizer's: a subset of the full mesh's vertices
  kUnbiased,  // moved so that the full surface lies on the level on average (the default)
};

class LodChain {
 public:
  // Level 0 is `mesh` itself (error 0). Coarser levels simplify to meshoptimizer target
  // errors of kFirstErrorM times 1, kErrorStep, kErrorStep^2 ... (while that still removes
  // triangles and keeps at least kMinTriangles), its vertices placed as `vertices` says; each
  // level's error_m is then measured against `mesh`, which on the YCB-Video meshes is 1.1-3.4x
  // meshoptimizer's own figure.
  // `mesh` must be valid (Mesh::Validate).
  static constexpr float kFirstErrorM = 0.00025f;
  // The ratio of successive target errors. sqrt(2) gives twice the levels, each chosen level
  // closer to the budget (the tomato can's 1402 -> 792 triangles), but no better accuracy
  // (docs/engine-notes.md).
  static constexpr float kErrorStep = 2.0f;
  static constexpr int kMaxLevels = 7;
  static constexpr size_t kMinTriangles = 64;
  static constexpr int kUnbiasRounds = 3;
  static constexpr size_t kUnbiasSamplesPerTriangle = 4;
  static LodChain Build(const Mesh& mesh, LodVertices vertices = LodVertices::kUnbiased);

  int num_levels() const { return static_cast<int>(levels_.size()); }
  const LodLevel& level(int i) const { return levels_[static_cast<size_t>(i)]; }

  // The coarsest level whose error is at most max_error_m (level 0 when none is).
  int Select(float max_error_m) const;

 private:
  std::vector<LodLevel> levels_;
};

// The error budget in metres of `error_px` pixels at depth z_m with focal length f_px
// (the smaller of fx, fy). error_px <= 0 disables LOD (returns 0: only level 0 fits).
float LodErrorBudgetM(float error_px, float z_m, float f_px);

// A 64-bit FNV-1a fingerprint of a mesh's vertices and triangles (for caching chains).
uint64_t MeshFingerprint(const Mesh& mesh);

}  // namespace mcpose::render

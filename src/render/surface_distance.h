// Distances between triangle-mesh surfaces, for measuring how far a simplified mesh (a level of
// detail, render/lod.h) strays from the full one. meshoptimizer reports a quadric error, which
// on the 112 simplified levels of the 21 YCB-Video meshes is 1.1-3.4x (mean 2.0x) below the
// largest distance measured here between the two surfaces; the level of detail is chosen by
// the measured one.
#pragma once

#include <span>
#include <vector>

#include <Eigen/Core>

#include "mcpose/mesh.h"

namespace mcpose::render {

// Squared distance from p to the triangle (a, b, c), by the Voronoi regions of its vertices,
// edges and face. Degenerate triangles (a segment or a point) are handled.
float PointTriangleDistanceSquared(const Eigen::Vector3f& p, const Eigen::Vector3f& a,
                                   const Eigen::Vector3f& b, const Eigen::Vector3f& c);

// Points that sample a mesh's surface: the vertices its triangles use, and the triangles'
// centroids and edge midpoints.
std::vector<Eigen::Vector3f> SurfaceSamples(const Mesh& mesh, bool vertices, bool centroids_and_edge_midpoints);

// A uniform grid over a mesh's triangles (each listed in every cell its bounding box meets),
// for nearest-surface queries. The mesh must outlive the grid. Queries keep scratch state in
// the grid: one grid is queried by one thread at a time.
class TriangleGrid {
 public:
  explicit TriangleGrid(const Mesh& mesh);

  // The distance from p to the nearest triangle, exact; but once a triangle nearer than
  // `enough` is found the search stops and returns that triangle's distance (<= enough).
  // An empty mesh gives +infinity.
  float Distance(const Eigen::Vector3f& p, float enough = 0.f) const;

  // The nearest triangle to p (its index in the mesh) and its distance, exact. An empty mesh
  // gives {UINT32_MAX, +infinity}.
  struct Nearest {
    uint32_t triangle;
    float distance;
  };
  Nearest NearestTriangle(const Eigen::Vector3f& p) const;

 private:
  Nearest Search(const Eigen::Vector3f& p, float enough) const;

  const Mesh& mesh_;
  Eigen::Vector3f lo_ = Eigen::Vector3f::Zero();
  float cell_ = 1.f;
  int n_[3] = {0, 0, 0};
  std::vector<uint32_t> start_;  // cell c's triangles are items_[start_[c] .. start_[c + 1])
  std::vector<uint32_t> items_;
  // The query that last tested each triangle (a triangle is listed in every cell it meets; a
  // query tests it once). Queries write it: one TriangleGrid serves one thread.
  mutable std::vector<uint32_t> tested_by_;
  mutable uint32_t query_ = 0;
};

// max over `points` of the distance to the surface of `mesh`, through a TriangleGrid.
float MaxDistanceToSurface(std::span<const Eigen::Vector3f> points, const Mesh& mesh);
// The reference: every point against every triangle.
float MaxDistanceToSurfaceReference(std::span<const Eigen::Vector3f> points, const Mesh& mesh);

// The distance from p to the triangle (a, b, c), signed positive where p lies in front of its
// face (on the side its counter-clockwise normal points to: outside a closed mesh whose
// triangles face outward).
float SignedDistanceToTriangle(const Eigen::Vector3f& p, const Eigen::Vector3f& a, const Eigen::Vector3f& b,
                               const Eigen::Vector3f& c);

// Where a full surface lies against a simplified one, sampled at the centroids of the full
// mesh's triangles 0, stride, 2 stride, ...: each centroid's nearest simplified triangle, the
// signed distance to it (SignedDistanceToTriangle), and the full triangle's area, the
// centroid's weight.
struct SurfaceOffset {
  uint32_t full_triangle;
  uint32_t nearest_triangle;
  float signed_m;
  float area_m2;
};
std::vector<SurfaceOffset> SurfaceOffsets(const Mesh& full, const Mesh& simplified, size_t stride = 1);
// The centroid of triangle t of `mesh`.
Eigen::Vector3f Centroid(const Mesh& mesh, uint32_t t);

// Area-weighted means of the offsets' signed distance (the simplified surface's bias: > 0
// where it lies inside the full one on average) and of their absolute value, metres.
struct OffsetMeans {
  double signed_m = 0, abs_m = 0;
};
OffsetMeans MeanOffsets(std::span<const SurfaceOffset> offsets);

// The sampled two-sided (Hausdorff) distance between the surface of a full mesh and its
// simplifications: the larger of the distance from the full mesh's vertices to the
// simplified surface, and from the simplified mesh's vertices, centroids and edge midpoints
// to the full one (a meshoptimizer simplification's vertices lie on the full mesh, but an
// unbiased level's do not: render/lod.h). Metres, as the meshes. The full mesh's grid and
// samples are built once; the full mesh must outlive the meter.
class DeviationMeter {
 public:
  explicit DeviationMeter(const Mesh& full);
  float Measure(const Mesh& simplified) const;

 private:
  TriangleGrid full_grid_;
  std::vector<Eigen::Vector3f> full_samples_;
};

// The reference for DeviationMeter::Measure: the same samples, every triangle tested.
float SampledDeviationReferenceM(const Mesh& full, const Mesh& simplified);

}  // namespace mcpose::render

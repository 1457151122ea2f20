#include "render/surface_distance.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

namespace mcpose::render {

namespace {

using Vec3 = Eigen::Vector3f;

float PointSegmentDistanceSquared(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const float len2 = ab.squaredNorm();
  const float t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.f, 1.f) : 0.f;
  return (p - (a + t * ab)).squaredNorm();
}

}  // namespace

float PointTriangleDistanceSquared(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  // Which Voronoi region of the triangle p projects into: a vertex, an edge or the face.
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const float d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return ap.squaredNorm();  // vertex a
  const Vec3 bp = p - b;
  const float d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return bp.squaredNorm();  // vertex b
  const Vec3 cp = p - c;
  const float d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return cp.squaredNorm();  // vertex c
  const float vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return PointSegmentDistanceSquared(p, a, b);
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return PointSegmentDistanceSquared(p, a, c);
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return PointSegmentDistanceSquared(p, b, c);
  const float sum = va + vb + vc;
  if (!(sum > 0)) {  // degenerate (collinear) triangle: the nearest of its edges
    return std::min({PointSegmentDistanceSquared(p, a, b), PointSegmentDistanceSquared(p, a, c),
                     PointSegmentDistanceSquared(p, b, c)});
  }
  const Vec3 q = a + ab * (vb / sum) + ac * (vc / sum);  // the projection onto the face
  return (p - q).squaredNorm();
}

std::vector<Vec3> SurfaceSamples(const Mesh& mesh, bool vertices, bool centroids_and_edge_midpoints) {
  std::vector<Vec3> out;
  if (vertices) {
    std::vector<bool> used(mesh.vertices_m.size(), false);
    for (const auto& t : mesh.triangles)
      for (uint32_t v : t) used[v] = true;
    for (size_t v = 0; v < used.size(); ++v)
      if (used[v]) out.push_back(mesh.vertices_m[v]);
  }
  if (centroids_and_edge_midpoints) {
    for (uint32_t i = 0; i < mesh.triangles.size(); ++i) {
      const auto& t = mesh.triangles[i];
      const Vec3 &a = mesh.vertices_m[t[0]], &b = mesh.vertices_m[t[1]], &c = mesh.vertices_m[t[2]];
      out.push_back(Centroid(mesh, i));
      out.push_back(0.5f * (a + b));
      out.push_back(0.5f * (b + c));
      out.push_back(0.5f * (c + a));
    }
  }
  return out;
}

namespace {

// floor(x) clamped to 0..n-1, defined for any float (NaN and values beyond int give an end cell;
// a plain cast of those would be undefined).
int ClampedCell(float x, int n) {
  if (!(x > 0.f)) return 0;
  if (x >= static_cast<float>(n - 1)) return n - 1;
  return static_cast<int>(x);
}

}  // namespace

TriangleGrid::TriangleGrid(const Mesh& mesh) : mesh_(mesh) {
  if (mesh.triangles.empty()) return;
  tested_by_.assign(mesh.triangles.size(), 0u);
  Vec3 lo = Vec3::Constant(std::numeric_limits<float>::infinity()), hi = -lo;
  for (const auto& t : mesh.triangles)
    for (uint32_t v : t) lo = lo.cwiseMin(mesh.vertices_m[v]), hi = hi.cwiseMax(mesh.vertices_m[v]);
  const float extent = (hi - lo).maxCoeff();
  // About 1.5 cube-root(triangles) cells along the longest side: a few triangles per cell.
  const int cells = std::clamp(static_cast<int>(1.5 * std::cbrt(static_cast<double>(mesh.triangles.size()))), 1, 64);
  cell_ = extent > 0 ? extent / static_cast<float>(cells) : 1.f;
  lo_ = lo;
  for (int k = 0; k < 3; ++k) n_[k] = ClampedCell((hi[k] - lo[k]) / cell_, cells + 1) + 1;

  auto cell_range = [&](const std::array<uint32_t, 3>& t, int k, int* c0, int* c1) {
    float a = mesh.vertices_m[t[0]][k], b = a;
    for (int i = 1; i < 3; ++i) a = std::min(a, mesh.vertices_m[t[i]][k]), b = std::max(b, mesh.vertices_m[t[i]][k]);
    *c0 = ClampedCell((a - lo_[k]) / cell_, n_[k]);
    *c1 = ClampedCell((b - lo_[k]) / cell_, n_[k]);
  };
  const size_t num_cells = static_cast<size_t>(n_[0]) * n_[1] * n_[2];
  start_.assign(num_cells + 1, 0);
  // Two passes (count, then fill) into one flat array.
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<uint32_t> fill;
    if (pass == 1) {
      for (size_t c = 0; c < num_cells; ++c) start_[c + 1] += start_[c];
      items_.resize(start_[num_cells]);
      fill.assign(start_.begin(), start_.end() - 1);
    }
    for (uint32_t i = 0; i < mesh.triangles.size(); ++i) {
      int r[3][2];
      for (int k = 0; k < 3; ++k) cell_range(mesh.triangles[i], k, &r[k][0], &r[k][1]);
      for (int z = r[2][0]; z <= r[2][1]; ++z)
        for (int y = r[1][0]; y <= r[1][1]; ++y)
          for (int x = r[0][0]; x <= r[0][1]; ++x) {
            const size_t c = (static_cast<size_t>(z) * n_[1] + y) * n_[0] + x;
            if (pass == 0) ++start_[c + 1];
            else items_[fill[c]++] = i;
          }
    }
  }
}

float TriangleGrid::Distance(const Vec3& p, float enough) const { return Search(p, enough).distance; }

TriangleGrid::Nearest TriangleGrid::NearestTriangle(const Vec3& p) const { return Search(p, 0.f); }

TriangleGrid::Nearest TriangleGrid::Search(const Vec3& p, float enough) const {
  if (mesh_.triangles.empty()) return {UINT32_MAX, std::numeric_limits<float>::infinity()};
  // The cell of p's nearest point in the grid's box, then rings of cells around it (cells r
  // away in the max norm), until the nearest triangle found is nearer than any cell outside.
  int c[3];
  for (int k = 0; k < 3; ++k) c[k] = ClampedCell((p[k] - lo_[k]) / cell_, n_[k]);
  if (++query_ == 0) {  // the counter wrapped: no triangle may look tested
    std::fill(tested_by_.begin(), tested_by_.end(), 0u);
    query_ = 1;
  }
  const float enough2 = enough * enough;
  float best2 = std::numeric_limits<float>::infinity();
  uint32_t best = UINT32_MAX;
  const int max_r = std::max({n_[0], n_[1], n_[2]});
  for (int r = 0; r <= max_r; ++r) {
    for (int z = std::max(0, c[2] - r); z <= std::min(n_[2] - 1, c[2] + r); ++z)
      for (int y = std::max(0, c[1] - r); y <= std::min(n_[1] - 1, c[1] + r); ++y)
        for (int x = std::max(0, c[0] - r); x <= std::min(n_[0] - 1, c[0] + r); ++x) {
          if (std::max({std::abs(x - c[0]), std::abs(y - c[1]), std::abs(z - c[2])}) != r) continue;
          const size_t cell = (static_cast<size_t>(z) * n_[1] + y) * n_[0] + x;
          for (uint32_t j = start_[cell]; j < start_[cell + 1]; ++j) {
            if (tested_by_[items_[j]] == query_) continue;
            tested_by_[items_[j]] = query_;
            const auto& t = mesh_.triangles[items_[j]];
            const float d2 =
                PointTriangleDistanceSquared(p, mesh_.vertices_m[t[0]], mesh_.vertices_m[t[1]], mesh_.vertices_m[t[2]]);
            if (d2 < best2) best2 = d2, best = items_[j];
          }
          if (best2 <= enough2) return {best, std::sqrt(best2)};
        }
    // Every triangle not yet tested lies only in cells outside the block of rings 0..r, so at
    // least as far from p as the nearest face of that block which is not the grid's own border
    // (no cells lie beyond those).
    float bound = std::numeric_limits<float>::infinity();
    for (int k = 0; k < 3; ++k) {
      if (c[k] - r > 0) bound = std::min(bound, p[k] - (lo_[k] + static_cast<float>(c[k] - r) * cell_));
      if (c[k] + r < n_[k] - 1) bound = std::min(bound, lo_[k] + static_cast<float>(c[k] + r + 1) * cell_ - p[k]);
    }
    bound *= 1.f - 1e-5f;  // float rounding of the faces' positions
    if (bound >= 0 && best2 <= bound * bound) break;
  }
  return {best, std::sqrt(best2)};
}

float MaxDistanceToSurface(std::span<const Vec3> points, const Mesh& mesh) {
  const TriangleGrid grid(mesh);
  float worst = 0;
  for (const Vec3& p : points) worst = std::max(worst, grid.Distance(p, worst));
  return worst;
}

float MaxDistanceToSurfaceReference(std::span<const Vec3> points, const Mesh& mesh) {
  float worst = 0;
  for (const Vec3& p : points) {
    float best2 = std::numeric_limits<float>::infinity();
    for (const auto& t : mesh.triangles)
      best2 = std::min(best2, PointTriangleDistanceSquared(p, mesh.vertices_m[t[0]], mesh.vertices_m[t[1]],
                                                           mesh.vertices_m[t[2]]));
    worst = std::max(worst, std::sqrt(best2));
  }
  return worst;
}

namespace {

// Whether p lies in front of the face (a, b, c) (or on its plane).
bool InFront(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  return (p - a).dot((b - a).cross(c - a)) >= 0;
}

}  // namespace

float SignedDistanceToTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const float d = std::sqrt(PointTriangleDistanceSquared(p, a, b, c));
  return InFront(p, a, b, c) ? d : -d;
}

Vec3 Centroid(const Mesh& mesh, uint32_t t) {
  const auto& v = mesh.triangles[t];
  return (mesh.vertices_m[v[0]] + mesh.vertices_m[v[1]] + mesh.vertices_m[v[2]]) / 3.f;
}

std::vector<SurfaceOffset> SurfaceOffsets(const Mesh& full, const Mesh& simplified, size_t stride) {
  std::vector<SurfaceOffset> out;
  if (simplified.triangles.empty()) return out;  // nothing to be near to
  stride = std::max<size_t>(stride, 1);
  out.reserve(full.triangles.size() / stride + 1);
  const TriangleGrid grid(simplified);
  for (size_t i = 0; i < full.triangles.size(); i += stride) {
    const auto& t = full.triangles[i];
    const Vec3 &a = full.vertices_m[t[0]], &b = full.vertices_m[t[1]], &c = full.vertices_m[t[2]];
    const Vec3 centroid = Centroid(full, static_cast<uint32_t>(i));
    const TriangleGrid::Nearest hit = grid.NearestTriangle(centroid);
    const auto& s = simplified.triangles[hit.triangle];
    const bool in_front = InFront(centroid, simplified.vertices_m[s[0]], simplified.vertices_m[s[1]],
                                  simplified.vertices_m[s[2]]);
    out.push_back({static_cast<uint32_t>(i), hit.triangle, in_front ? hit.distance : -hit.distance,
                   0.5f * (b - a).cross(c - a).norm()});
  }
  return out;
}

OffsetMeans MeanOffsets(std::span<const SurfaceOffset> offsets) {
  double area = 0;
  OffsetMeans m;
  for (const SurfaceOffset& o : offsets) {
    area += o.area_m2;
    m.signed_m += static_cast<double>(o.area_m2) * o.signed_m;
    m.abs_m += static_cast<double>(o.area_m2) * std::fabs(o.signed_m);
  }
  if (area > 0) m.signed_m /= area, m.abs_m /= area;
  return m;
}

DeviationMeter::DeviationMeter(const Mesh& full)
    : full_grid_(full), full_samples_(SurfaceSamples(full, /*vertices=*/true, /*centroids_and_edge_midpoints=*/false)) {}

float DeviationMeter::Measure(const Mesh& simplified) const {
  float worst = MaxDistanceToSurface(full_samples_, simplified);
  for (const Vec3& p : SurfaceSamples(simplified, /*vertices=*/true, /*centroids_and_edge_midpoints=*/true))
    worst = std::max(worst, full_grid_.Distance(p, worst));
  return worst;
}

float SampledDeviationReferenceM(const Mesh& full, const Mesh& simplified) {
  return std::max(
      MaxDistanceToSurfaceReference(SurfaceSamples(full, true, false), simplified),
      MaxDistanceToSurfaceReference(SurfaceSamples(simplified, true, true), full));
}

}  // namespace mcpose::render

#include "render/lod.h"

#include <algorithm>
#include <cstring>

#include <Eigen/Geometry>
#include <meshoptimizer.h>

#include "core/check.h"
#include "render/surface_distance.h"

namespace mcpose::render {

namespace {

// Keeps the used vertices of `indices` (in first-use order) and rewrites the indices.
Mesh Compact(const Mesh& full, const std::vector<uint32_t>& indices) {
  std::vector<uint32_t> remap(full.vertices_m.size(), UINT32_MAX);
  Mesh out;
  out.triangles.resize(indices.size() / 3);
  for (size_t i = 0; i < indices.size(); ++i) {
    uint32_t& r = remap[indices[i]];
    if (r == UINT32_MAX) {
      r = static_cast<uint32_t>(out.vertices_m.size());
      out.vertices_m.push_back(full.vertices_m[indices[i]]);
    }
    out.triangles[i / 3][i % 3] = r;
  }
  return out;
}

// Moves each vertex of `level` along its area-weighted normal by the area-weighted mean signed
// offset of the full surface from the level triangles that use it, `rounds` times, each from
// the moved level. The full surface is sampled at about kUnbiasSamplesPerTriangle centroids
// of full triangles per level triangle (every stride-th full triangle); each sample counts for
// the three vertices of its nearest level triangle, found once, in the first round (later
// rounds measure the sample's signed distance to the moved triangle). A vertex no sample is
// nearest to, or without a normal, stays.
void Unbias(const Mesh& full, int rounds, Mesh* level) {
  const size_t nv = level->vertices_m.size();
  const size_t stride = std::max<size_t>(
      1, (full.triangles.size() + LodChain::kUnbiasSamplesPerTriangle * level->triangles.size() - 1) /
             (LodChain::kUnbiasSamplesPerTriangle * level->triangles.size()));
  std::vector<SurfaceOffset> offsets = SurfaceOffsets(full, *level, stride);
  std::vector<Eigen::Vector3f> normals(nv);
  std::vector<double> sum(nv), weight(nv);
  for (int r = 0; r < rounds; ++r) {
    if (r > 0) {
      for (SurfaceOffset& o : offsets) {
        const auto& t = level->triangles[o.nearest_triangle];
        o.signed_m = SignedDistanceToTriangle(Centroid(full, o.full_triangle), level->vertices_m[t[0]],
                                              level->vertices_m[t[1]], level->vertices_m[t[2]]);
      }
    }
    std::fill(normals.begin(), normals.end(), Eigen::Vector3f::Zero());
    for (const auto& t : level->triangles) {
      const Eigen::Vector3f& v0 = level->vertices_m[t[0]];
      const Eigen::Vector3f n = (level->vertices_m[t[1]] - v0).cross(level->vertices_m[t[2]] - v0);
      for (uint32_t v : t) normals[v] += n;  // |n| = twice the area: area-weighted
    }
    std::fill(sum.begin(), sum.end(), 0.0);
    std::fill(weight.begin(), weight.end(), 0.0);
    for (const SurfaceOffset& o : offsets)
      for (uint32_t v : level->triangles[o.nearest_triangle]) {
        sum[v] += o.area_m2 * o.signed_m;
        weight[v] += o.area_m2;
      }
    for (size_t v = 0; v < nv; ++v)
      if (weight[v] > 0 && normals[v].norm() > 0)
        level->vertices_m[v] += static_cast<float>(sum[v] / weight[v]) * normals[v].normalized();
  }
}

}  // namespace

LodChain LodChain::Build(const Mesh& mesh, LodVertices vertices) {
  LodChain chain;
  chain.levels_.push_back(LodLevel{mesh, 0.f, 0.f, ClusterSet::Build(mesh)});
  if (mesh.triangles.size() <= kMinTriangles) return chain;

  std::vector<uint32_t> indices(mesh.triangles.size() * 3);
  std::memcpy(indices.data(), mesh.triangles.data(), indices.size() * sizeof(uint32_t));
  static_assert(sizeof(std::array<uint32_t, 3>) == 3 * sizeof(uint32_t));
  const float* positions = mesh.vertices_m.front().data();
  const size_t stride = sizeof(Eigen::Vector3f);
  static_assert(sizeof(Eigen::Vector3f) == 3 * sizeof(float));
  // meshoptimizer errors are relative to the mesh extent; this converts them to metres.
  const float scale = meshopt_simplifyScale(positions, mesh.vertices_m.size(), stride);
  if (!(scale > 0)) return chain;

  const DeviationMeter meter(mesh);
  std::vector<uint32_t> out(indices.size());
  // Errors kFirstErrorM * kErrorStep^k up to the mesh extent; a level is kept only if it removes
  // triangles, and simplification stops at kMinTriangles.
  for (float target_m = kFirstErrorM; target_m <= scale && chain.num_levels() < kMaxLevels;
       target_m *= kErrorStep) {
    float result_error = 0;
    const size_t n = meshopt_simplify(out.data(), indices.data(), indices.size(), positions,
                                      mesh.vertices_m.size(), stride, kMinTriangles * 3,
                                      target_m / scale, /*options=*/0, &result_error);
    const size_t prev = chain.levels_.back().mesh.triangles.size();
    if (n >= 3 && n / 3 < prev) {
      std::vector<uint32_t> kept(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(n));
      Mesh level = Compact(mesh, kept);
      // The measured deviation of meshoptimizer's level (or the reported error if larger),
      // never below the previous level's: errors must grow along the chain for Select. It is
      // measured before unbiasing, so the vertex placement does not change which level a box
      // draws.
      const float reported = result_error * scale;
      const float err = std::max({meter.Measure(level), reported, chain.levels_.back().error_m});
      if (vertices == LodVertices::kUnbiased) Unbias(mesh, kUnbiasRounds, &level);
      ClusterSet clusters = ClusterSet::Build(level);
      chain.levels_.push_back(LodLevel{std::move(level), err, reported, std::move(clusters)});
    }
    if (n <= kMinTriangles * 3) break;
  }
  return chain;
}

int LodChain::Select(float max_error_m) const {
  int best = 0;
  for (int i = 1; i < num_levels(); ++i)
    if (levels_[static_cast<size_t>(i)].error_m <= max_error_m) best = i;
  return best;
}

float LodErrorBudgetM(float error_px, float z_m, float f_px) {
  if (!(error_px > 0) || !(z_m > 0) || !(f_px > 0)) return 0.f;
  return error_px * z_m / f_px;
}

uint64_t MeshFingerprint(const Mesh& mesh) {
  uint64_t h = 1469598103934665603ull;
  auto mix = [&h](const void* data, size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 1099511628211ull;
  };
  const uint64_t nv = mesh.vertices_m.size(), nt = mesh.triangles.size();
  mix(&nv, sizeof nv);
  mix(&nt, sizeof nt);
  if (nv) mix(mesh.vertices_m.data(), nv * sizeof(Eigen::Vector3f));
  if (nt) mix(mesh.triangles.data(), nt * sizeof(std::array<uint32_t, 3>));
  return h;
}

}  // namespace mcpose::render

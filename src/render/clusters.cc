#include "render/clusters.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>
#include <meshoptimizer.h>

namespace mcpose::render {

ClusterSet ClusterSet::Build(const Mesh& mesh) {
  ClusterSet out;
  std::vector<unsigned int> indices;
  indices.reserve(mesh.triangles.size() * 3);
  for (const auto& t : mesh.triangles) indices.insert(indices.end(), {t[0], t[1], t[2]});
  const size_t max_meshlets = meshopt_buildMeshletsBound(indices.size(), kMaxVertices, kMaxTriangles);
  std::vector<meshopt_Meshlet> meshlets(max_meshlets);
  std::vector<unsigned int> meshlet_vertices(max_meshlets * kMaxVertices);
  std::vector<unsigned char> meshlet_triangles(max_meshlets * kMaxTriangles * 3);
  const float* positions = mesh.vertices_m.data()->data();
  const size_t count = meshopt_buildMeshlets(meshlets.data(), meshlet_vertices.data(), meshlet_triangles.data(),
                                         indices.data(), indices.size(), positions, mesh.vertices_m.size(),
                                         sizeof(Eigen::Vector3f), kMaxVertices, kMaxTriangles, /*cone_weight=*/0.5f);
  out.triangles.reserve(mesh.triangles.size());
  for (size_t m = 0; m < count; ++m) {
    const meshopt_Meshlet& ml = meshlets[m];
    const meshopt_Bounds b = meshopt_computeMeshletBounds(
        &meshlet_vertices[ml.vertex_offset], &meshlet_triangles[ml.triangle_offset], ml.triangle_count, positions,
        mesh.vertices_m.size(), sizeof(Eigen::Vector3f));
    Cluster c;
    c.first = static_cast<uint32_t>(out.triangles.size());
    c.count = ml.triangle_count;
    c.center = Eigen::Vector3f(b.center[0], b.center[1], b.center[2]);
    c.radius = b.radius;
    // Over the cluster's vertices (the meshlet's vertex list: those its triangles use): their
    // bounds, and the sphere grown to hold them all (meshoptimizer's leaves out the vertices of
    // zero-area triangles, which snapping can still turn into covered pixels).
    c.box_lo = c.box_hi = mesh.vertices_m[meshlet_vertices[ml.vertex_offset]];
    for (unsigned int k = 0; k < ml.vertex_count; ++k) {
      const Eigen::Vector3f& v = mesh.vertices_m[meshlet_vertices[ml.vertex_offset + k]];
      c.box_lo = c.box_lo.cwiseMin(v), c.box_hi = c.box_hi.cwiseMax(v);
      c.radius = std::max(c.radius, (v - c.center).norm());
    }
    c.cone_apex = Eigen::Vector3f(b.cone_apex[0], b.cone_apex[1], b.cone_apex[2]);
    c.cone_axis = Eigen::Vector3f(b.cone_axis[0], b.cone_axis[1], b.cone_axis[2]);
    c.cone_cutoff = b.cone_cutoff;
    // meshoptimizer leaves triangles of (near) zero area out of the cone; snapped to the pixel
    // grid such a sliver can still face the camera. A cluster with one, or with a normal
    // outside its cone, is never dropped as back-facing.
    const double cos_half = std::sqrt(std::max(0.0, 1.0 - double(c.cone_cutoff) * c.cone_cutoff));
    bool cone_holds = c.cone_cutoff < 1.0f;
    for (unsigned int k = 0; k < ml.triangle_count; ++k) {
      const unsigned char* lt = &meshlet_triangles[ml.triangle_offset + 3 * k];
      const std::array<uint32_t, 3> tri = {meshlet_vertices[ml.vertex_offset + lt[0]],
                                           meshlet_vertices[ml.vertex_offset + lt[1]],
                                           meshlet_vertices[ml.vertex_offset + lt[2]]};
      out.triangles.push_back(tri);
      const Eigen::Vector3d p0 = mesh.vertices_m[tri[0]].cast<double>(), p1 = mesh.vertices_m[tri[1]].cast<double>(),
                            p2 = mesh.vertices_m[tri[2]].cast<double>();
      const Eigen::Vector3d normal = (p1 - p0).cross(p2 - p0);
      const double edge2 = std::max({(p1 - p0).squaredNorm(), (p2 - p0).squaredNorm(), (p2 - p1).squaredNorm()});
      // Slivers: area below 1% of the longest edge squared.
      if (!(normal.norm() > 0.01 * edge2) || normal.normalized().dot(c.cone_axis.cast<double>()) < cos_half - 1e-6)
        cone_holds = false;
    }
    if (!cone_holds) c.cone_cutoff = 1.0f;
    out.clusters.push_back(c);
  }
  out.BuildSoa();
  return out;
}

void ClusterSet::BuildSoa() {
  const size_t n = clusters.size();
  soa_stride = (n + kSoaLanes - 1) / kSoaLanes * kSoaLanes;
  soa.assign(soa_stride * kClusterFields, 0.0f);
  for (size_t i = 0; i < soa_stride && n > 0; ++i) {
    const Cluster& c = clusters[std::min(i, n - 1)];
    const float fields[kClusterFields] = {
        c.cone_apex.x(), c.cone_apex.y(), c.cone_apex.z(), c.cone_axis.x(), c.cone_axis.y(), c.cone_axis.z(),
        c.cone_cutoff,   c.center.x(),    c.center.y(),    c.center.z(),    c.radius,        c.box_lo.x(),
        c.box_lo.y(),    c.box_lo.z(),    c.box_hi.x(),    c.box_hi.y(),    c.box_hi.z()};
    for (int f = 0; f < kClusterFields; ++f) soa[f * soa_stride + i] = fields[f];
  }
}

ClusterCull CullCluster(const Cluster& c, const Eigen::Matrix3f& R, const Eigen::Vector3f& t,
                        const Eigen::Vector3f& camera_in_model, const RasterParams& params) {
  // Back-facing (when back faces are culled): meshoptimizer's perspective cone test, with a
  // margin.
  if (params.cull_backfaces && c.cone_cutoff < 1.0f - kConeMargin) {
    const Eigen::Vector3f view = c.cone_apex - camera_in_model;
    const float len = view.norm();
    if (len > 0 && view.dot(c.cone_axis) >= (c.cone_cutoff + kConeMargin) * len) return ClusterCull::kBackface;
  }
  // Outside the box: bound the projection of the sphere's bounding cube. With every point's
  // depth in [z - r, z + r] > 0, x / z over the cube lies between its values at the corners
  // (monotone in x and in z), so u lies between fx * min(x / z) + cx and fx * max(x / z) + cx.
  const Eigen::Vector3f p = R * c.center + t;
  const float r = c.radius, z0 = p.z() - r, z1 = p.z() + r;
  if (!(z0 > params.z_near_m)) return ClusterCull::kKeep;  // near the camera: per triangle
  const float i0 = 1.0f / z0, i1 = 1.0f / z1;
  auto range = [&](float xc, float f, float cc, float* lo, float* hi) {
    const float a = xc - r, b = xc + r;
    *lo = f * std::min({a * i0, a * i1}) + cc;
    *hi = f * std::max({b * i0, b * i1}) + cc;
  };
  float u0, u1, v0, v1;
  range(p.x(), params.fx, params.cx, &u0, &u1);
  range(p.y(), params.fy, params.cy, &v0, &v1);
  // One pixel of slack for rounding and sub-pixel snapping; pixel centres are at integers.
  const PixelRect& box = params.box;
  if (u1 < box.x0 - 1.0f || u0 > box.x1 || v1 < box.y0 - 1.0f || v0 > box.y1) return ClusterCull::kOutsideBox;
  // Tighter, for clusters the sphere keeps: the bounds of its vertices' box. With its 8 corners
  // in front of the near plane, the box projects into the convex hull of their projections.
  float cu0 = INFINITY, cu1 = -INFINITY, cv0 = INFINITY, cv1 = -INFINITY;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3f corner((k & 1) ? c.box_hi.x() : c.box_lo.x(), (k & 2) ? c.box_hi.y() : c.box_lo.y(),
                                 (k & 4) ? c.box_hi.z() : c.box_lo.z());
    const Eigen::Vector3f q = R * corner + t;
    if (!(q.z() > params.z_near_m)) return ClusterCull::kKeep;
    const float iz = 1.0f / q.z();
    const float cu = params.fx * q.x() * iz + params.cx, cv = params.fy * q.y() * iz + params.cy;
    cu0 = std::min(cu0, cu), cu1 = std::max(cu1, cu), cv0 = std::min(cv0, cv), cv1 = std::max(cv1, cv);
  }
  if (cu1 < box.x0 - 1.0f || cu0 > box.x1 || cv1 < box.y0 - 1.0f || cv0 > box.y1) return ClusterCull::kOutsideBox;
  return ClusterCull::kKeep;
}

std::span<const std::array<uint32_t, 3>> KeptTriangles(const ClusterSet& set, const ClusterCull* culls,
                                                       std::vector<std::array<uint32_t, 3>>* scratch,
                                                       RasterCounters* stats) {
  // Runs of adjacent kept clusters are referenced in place, and copied out together only when
  // a dropped cluster splits them.
  const std::span<const std::array<uint32_t, 3>> all(set.triangles);
  scratch->clear();
  size_t run_first = 0, run_end = 0;  // the current run of kept triangles in `all`
  for (size_t k = 0; k < set.clusters.size(); ++k) {
    const Cluster& c = set.clusters[k];
    switch (culls[k]) {
      case ClusterCull::kBackface:
        ++stats->clusters_culled_backface;
        stats->culled_backface += c.count;
        break;
      case ClusterCull::kOutsideBox:
        ++stats->clusters_culled_outside_box;
        stats->culled_outside_box += c.count;
        break;
      case ClusterCull::kKeep:
        if (run_end != c.first) {  // a new run: the previous one is copied out
          scratch->insert(scratch->end(), all.begin() + run_first, all.begin() + run_end);
          run_first = c.first;
        }
        run_end = c.first + c.count;
        continue;
    }
    stats->triangles_in += c.count;
  }
  stats->clusters += static_cast<int64_t>(set.clusters.size());
  std::span<const std::array<uint32_t, 3>> kept = all.subspan(run_first, run_end - run_first);
  if (!scratch->empty()) {  // runs were copied out: the last one joins them
    scratch->insert(scratch->end(), kept.begin(), kept.end());
    kept = *scratch;
  }
  return kept;
}

}  // namespace mcpose::render

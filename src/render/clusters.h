// Cluster culling for the raster cores: a mesh split by meshoptimizer into clusters (meshlets)
// of up to 16 triangles, each with a bounding sphere and a normal cone, so that whole clusters
// that lie outside a sample's box or face away from its camera are dropped before triangle
// setup. The box test is conservative (a dropped cluster's triangles all miss the box by more
// than a pixel). The back-facing test is meshoptimizer's normal cone with a margin, and is
// conservative in exact geometry, not quite on the snapped pixel grid: on real meshes it drops
// about 1 covered pixel in a million (a triangle the per-triangle path rasterized), and the
// inlier counts stayed identical to the per-triangle path (tests/engine_real_test.cc).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "mcpose/mesh.h"
#include "render/raster.h"

namespace mcpose::render {

struct Cluster {
  uint32_t first = 0, count = 0;  // its triangles: ClusterSet::triangles[first, first + count)
  Eigen::Vector3f center = Eigen::Vector3f::Zero();  // bounding sphere, model frame, metres
  float radius = 0;
  Eigen::Vector3f cone_apex = Eigen::Vector3f::Zero();  // normal cone (meshoptimizer's)
  Eigen::Vector3f cone_axis = Eigen::Vector3f::Zero();
  float cone_cutoff = 1;  // cos of the half angle; >= 1 means no usable cone
  Eigen::Vector3f box_lo = Eigen::Vector3f::Zero(), box_hi = Eigen::Vector3f::Zero();  // its vertices' bounds
};

// The fields of Cluster that culling reads, in the order of ClusterSet::soa.
enum ClusterField : int {
  kApexX, kApexY, kApexZ, kAxisX, kAxisY, kAxisZ, kCutoff, kCenterX, kCenterY, kCenterZ, kRadius,
  kBoxLoX, kBoxLoY, kBoxLoZ, kBoxHiX, kBoxHiY, kBoxHiZ, kClusterFields
};

struct ClusterSet {
  std::vector<std::array<uint32_t, 3>> triangles;  // the mesh's triangles, grouped by cluster
  std::vector<Cluster> clusters;
  // The same clusters as structure of arrays for CullClustersSimd: field f of cluster i at
  // soa[f * soa_stride + i]; soa_stride is clusters.size() rounded up to kSoaLanes, and the
  // lanes past the last cluster repeat it.
  std::vector<float> soa;
  size_t soa_stride = 0;
  static constexpr size_t kSoaLanes = 16;
  static constexpr size_t kMaxTriangles = 16;  // 8, 32 and 64 measured slower: docs/engine-notes.md
  static constexpr size_t kMaxVertices = 16;
  // Every triangle of `mesh` lands in exactly one cluster (same vertex indices).
  static ClusterSet Build(const Mesh& mesh);
  // Fills soa from clusters (Build calls it).
  void BuildSoa();
};

enum class ClusterCull : uint8_t { kKeep, kBackface, kOutsideBox };

// The cone margin: a cluster is dropped as back-facing only when the view direction is this
// much (in cosine) inside its back-facing cone, so snapping cannot turn one of its triangles.
inline constexpr float kConeMargin = 0.05f;

// X_cam = R X + t; `camera_in_model` = -R^T t. Conservative (see the file comment). Never
// kBackface where params.cull_backfaces is false.
// The reference: one cluster at a time.
ClusterCull CullCluster(const Cluster& c, const Eigen::Matrix3f& R, const Eigen::Vector3f& t,
                        const Eigen::Vector3f& camera_in_model, const RasterParams& params);
// CullCluster for every cluster of `set`, a SIMD vector of clusters at a time
// (render/clusters_simd.cc, Highway, runtime-dispatched): out[i] for set.clusters[i], the same
// float operations in the same order, so the same decisions (tested on every target).
void CullClustersSimd(const ClusterSet& set, const Eigen::Matrix3f& R, const Eigen::Vector3f& t,
                      const Eigen::Vector3f& camera_in_model, const RasterParams& params, ClusterCull* out);

// The triangles of the clusters `culls` keeps (culls[k] for set.clusters[k]), in cluster order:
// a span into set.triangles when the kept clusters form one run, else copied into *scratch.
// Counts each dropped cluster and its triangles (as culled_backface or culled_outside_box, and
// in `triangles`, the triangles submitted) and the clusters tested in *stats.
std::span<const std::array<uint32_t, 3>> KeptTriangles(const ClusterSet& set, const ClusterCull* culls,
                                                       std::vector<std::array<uint32_t, 3>>* scratch,
                                                       RasterCounters* stats);

}  // namespace mcpose::render

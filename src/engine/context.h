// The engine context: what every estimate of one configuration shares. It owns the raster
// cores (thread pool, per-core scratch, the chosen backend) and the level-of-detail chains of
// the meshes seen so far. The estimator, `mcpose bench` and the diagnostics each build one and
// score through BoxScorer (engine/box_scorer.h); nothing else wires boxes to counts.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "score/colour_grid.h"
#include "core/rest_pose.h"
#include "engine/raster_cores.h"
#include "mcpose/mesh.h"
#include "mcpose/options.h"
#include "mcpose/status.h"
#include "render/lod.h"

namespace mcpose::engine {

// A mesh's stable rest poses (core/rest_pose.h) and what the initialization draws them by.
struct MeshRests {
  std::vector<RestPose> rests;     // lowest first
  std::vector<double> area_cdf;    // cumulative share of the rest faces' areas, last = 1
  Eigen::Vector3d centre_of_mass = Eigen::Vector3d::Zero();
};

// Ok if this CPU has the options' SIMD target (EngineOptions::simd_target), else an error
// naming it and the targets the CPU has.
Status CheckSimdTarget(const EngineOptions& engine);

class Context {
 public:
  // `options` must be valid (EstimatorOptions::IsValid).
  explicit Context(const EstimatorOptions& options);
  // A context of other options that shares `caches_from`'s LOD chains and colour grids (its
  // engine and appearance options must build the same ones: the tracker's two configurations).
  Context(const EstimatorOptions& options, const Context& caches_from);

  const EstimatorOptions& options() const { return options_; }
  // The scope that makes a thread dispatch the SIMD kernels to the options' target: the pool's
  // threads run inside it; an entry point that runs kernels on its own thread enters it too.
  ThreadScope simd_scope() const;
  RasterCores& cores() { return cores_; }
  ThreadPool& pool() { return cores_.pool(); }

  // The LOD chain of `mesh`, built on first use and cached by the mesh's content; null with
  // LOD off. Thread-safe: chains are built outside the lock, and a chain built twice at the
  // same time is the same chain (the first is kept).
  std::shared_ptr<const render::LodChain> Lod(const Mesh& mesh);
  // The colour grid of `mesh`'s appearance, baked on first use and cached by its content;
  // null when the mesh has no colour or the options turn colour off. Thread-safe, as Lod.
  std::shared_ptr<const appearance::ColourGrid> Colour(const Mesh& mesh);
  // The extreme points of `mesh` the box fit projects (score/box_fit.h), found on first use and
  // cached by its content; null when the options turn the box fit off. Thread-safe, as Lod.
  std::shared_ptr<const std::vector<Eigen::Vector3d>> Extremes(const Mesh& mesh);
  // The stable rest poses of `mesh`, found on first use and cached by its content; null when
  // the options start no sample at rest (init.rest_share 0) or the mesh has no convex hull.
  // Thread-safe, as Lod.
  std::shared_ptr<const MeshRests> Rests(const Mesh& mesh);
  // Builds the chains, colour grids, extreme points and rest poses of these meshes now, one mesh
  // per raster core.
  void PrepareMeshes(std::span<const Mesh* const> meshes);

 private:
  EstimatorOptions options_;
  RasterCores cores_;
  struct Caches {
    std::mutex mutex;  // guards the maps
    std::map<uint64_t, std::shared_ptr<const render::LodChain>> lod;
    std::map<uint64_t, std::shared_ptr<const appearance::ColourGrid>> colour;
    std::map<uint64_t, std::shared_ptr<const std::vector<Eigen::Vector3d>>> extremes;
    std::map<uint64_t, std::shared_ptr<const MeshRests>> rests;
  };
  std::shared_ptr<Caches> caches_ = std::make_shared<Caches>();
};

// Enters a context's SIMD scope (Context::simd_scope) on the calling thread for its lifetime.
class SimdScopeGuard {
 public:
  explicit SimdScopeGuard(const Context& context) : scope_(context.simd_scope()) {
    if (scope_.enter) scope_.enter();
  }
  ~SimdScopeGuard() {
    if (scope_.leave) scope_.leave();
  }
  SimdScopeGuard(const SimdScopeGuard&) = delete;
  SimdScopeGuard& operator=(const SimdScopeGuard&) = delete;

 private:
  ThreadScope scope_;
};

}  // namespace mcpose::engine

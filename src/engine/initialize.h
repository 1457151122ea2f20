// Step 1 of the filter: N samples over all boxes of one class, in proportion to score.
// Translation: the ray through the box centre at the `init_depth_quantile` of the box's valid
// observed depths plus half the object's median side (or, without valid depth, the distance
// at which the object would fill the box), jittered by init_sigma_t_m; rotation: uniform on
// SO(3). Sample i draws from its own random stream (seed, stream_id, init, i).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "engine/raster_cores.h"
#include "filter/particles.h"
#include "mcpose/detection.h"
#include "mcpose/mesh.h"
#include "mcpose/options.h"
#include "render/lod.h"

namespace mcpose::engine {

// The initial depth of the samples of box `d`: the `depth_quantile` of its valid observed
// depths plus half the object's median side, or, without valid depth, the distance at which
// the object's diameter would fill the box diagonal.
double InitialDepth(const Intrinsics& K, const Mesh& mesh, const Detection& d, const BoxDepth& box,
                    double depth_quantile);

// The LOD level box `d` renders: the coarsest level of `lod` whose measured deviation from the
// full mesh is at most options.lod_error_px image pixels at the box's initial depth (0 when LOD
// is off). Image pixels, whatever the box's pixel stride: a coarser scoring grid does not make
// a coarser mesh safe (the README's accuracy section: LOD and depth twins).
int SelectLodLevel(const render::LodChain& lod, const Intrinsics& K, const Mesh& mesh, const Detection& d,
                   const BoxDepth& box, const EstimatorOptions& options);

// The mesh each box renders and its culling clusters, as the estimator chooses them. With LOD on
// (options.lod_error_px > 0): the level SelectLodLevel picks from `lod`, the chain of `mesh`,
// and with options.cluster_culling that level's clusters. With LOD off: `mesh` and no clusters
// (`lod` may be null). `box_mesh` gets one entry per box; `box_clusters` one per box or none.
void ChooseBoxMeshes(const render::LodChain* lod, const Intrinsics& K, const Mesh& mesh,
                     std::span<const Detection> boxes, std::span<const BoxDepth> box_depth,
                     const EstimatorOptions& options, std::vector<const Mesh*>* box_mesh,
                     std::vector<const render::ClusterSet*>* box_clusters);

void InitializeSamples(const Intrinsics& K, const Mesh& mesh, std::span<const Detection> boxes,
                       std::span<const BoxDepth> box_depth, const EstimatorOptions& options,
                       uint64_t stream_id, filter::ParticleSet* particles);

}  // namespace mcpose::engine

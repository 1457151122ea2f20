// Step 1 of the filter: N samples over all boxes of one class, in proportion to score.
// Rotation: uniform on SO(3). Translation, jittered by init.sigma_t_m, on the ray through the
// box centre: for init.front_share of each box's samples, at the depth that puts the turned
// model's nearest point at the `init.front_quantile` of the box's valid observed depths; for the
// others, the model's origin at InitialDepth (options.h, InitOptions, says why both); for
// init.rest_share of them, where the box stands on a plane (FindSupportPlane), at rest on that
// plane instead. Sample i draws from its own random stream (seed, stream_id, init, i); the
// shares draw nothing.
#pragma once

#include <cstdint>
#include <optional>

#include <Eigen/Core>

#include "filter/particles.h"
#include "mcpose/camera.h"
#include "mcpose/detection.h"
#include "mcpose/mesh.h"
#include "mcpose/options.h"
#include "render/lod.h"
#include "score/box_observation.h"

namespace mcpose::engine {

class BoxScorer;

// A plane n . x + offset = 0 in the camera frame, its normal towards the camera (offset > 0).
struct SupportPlane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset = 0;
  double share = 0;  // of the ring's points within kPlaneInlierM of it
};
inline constexpr double kPlaneInlierM = 0.01;

// The plane box `d` stands on: the plane with the most points of the depth around the box (the
// box grown by half its size a side, the box left out) within kPlaneInlierM, found by RANSAC
// (200 tries, its own random stream per box), kept only where it holds at least 30 % of those
// points and the median point inside the box does not lie behind it.
std::optional<SupportPlane> FindSupportPlane(const DepthImage& depth, const Intrinsics& K, const Detection& d,
                                             uint64_t seed, uint64_t stream_id, int box_index);

// The initial depth of the samples of box `d`: the `depth_quantile` of its valid observed
// depths plus half the object's median side, or, without valid depth, the distance at which
// the object's diameter would fill the box diagonal.
double InitialDepth(const Intrinsics& K, const Mesh& mesh, const Detection& d, const score::BoxObservation& box,
                    double depth_quantile);

// The LOD level box `d` renders: the coarsest level of `lod` whose measured deviation from the
// full mesh is at most options.engine.lod_error_px image pixels at the box's initial depth.
// Image pixels, whatever the box's pixel stride: a coarser scoring grid does not make a coarser
// mesh safe (docs/engine-notes.md).
int SelectLodLevel(const render::LodChain& lod, const Intrinsics& K, const Mesh& mesh, const Detection& d,
                   const score::BoxObservation& box, const EstimatorOptions& options);

// `count` samples over the boxes of `scorer` in proportion to their scores (options.samples
// when left out; the filter's first generation holds options.samples * options.init.wide).
// Sample i draws from Rng(options.seed, stream_id, kInitStream, i).
void InitializeSamples(const BoxScorer& scorer, const EstimatorOptions& options, uint64_t stream_id,
                       filter::ParticleSet* particles, int count = -1);

}  // namespace mcpose::engine

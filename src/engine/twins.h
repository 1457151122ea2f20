// Twin resolution: after the filter, the best pose and the poses depth alone cannot tell from
// it are scored finely with colour, and the best is refined by a short run of the filter.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/box_scorer.h"
#include "mcpose/estimator.h"
#include "mcpose/se3.h"

namespace mcpose::engine {

// The model axis (0, 1, 2) whose bounding-box extent lies farthest from the mean of the other
// two: a can's or a bottle's axis of revolution.
int DistinctAxis(const Mesh& mesh);

// The twin candidates of pose T: T turned about the mesh's bounding-box centre by F then by
// k * step_deg about DistinctAxis (k = 0 .. 360 / step_deg - 1), for F the identity and the
// 180-degree turns about model x, y and z, each turn once (with a step that divides 180 degrees,
// 2 * 360 / step_deg of them). Candidate 0 is T itself.
std::vector<SE3> TwinCandidates(const SE3& T, const Mesh& mesh, double step_deg);

// Resolves the twins of `filtered` (the filter's answer of `scorer`, whose weight has its colour
// term): aligns each candidate to the depth (options.refine, when enabled), scores them with
// `full` (a full-resolution scorer of the chosen box alone, on the same raster cores), keeps the
// best, refines it with the filter (options.appearance), and returns the estimate with its
// `twins` record filled. Deterministic for (options.seed, stream_id).
ObjectEstimate ResolveTwins(Context& context, BoxScorer& scorer, BoxScorer& full, const DepthImage& depth,
                            ObjectEstimate filtered, uint64_t stream_id);

}  // namespace mcpose::engine

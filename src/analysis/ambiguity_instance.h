// The per-instance step of the depth-ambiguity analysis (mcpose/analysis/depth_ambiguity.h).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "mcpose/analysis/depth_ambiguity.h"
#include "render/raster.h"

namespace mcpose::analysis {

// The distinct candidate rotations S (model frame) for a step: identity first.
std::vector<Eigen::Matrix3d> CandidateRotations(double step_deg);

// One instance: the ground truth `T_gt` of `mesh` seen in `box` of the observed `depth`.
// `points` are the evaluation points; `symmetric` selects ADD-S instead of ADD.
InstanceAmbiguity AnalyzeInstance(const Intrinsics& K, const DepthImage& depth, const Mesh& mesh,
                                  const std::vector<Eigen::Vector3f>& points, const SE3& T_gt,
                                  const render::PixelRect& box, bool symmetric,
                                  const AmbiguityOptions& options);

}  // namespace mcpose::analysis

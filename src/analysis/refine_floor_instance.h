// The per-instance steps of the refinement floor (mcpose/analysis/refine_floor.h).
#pragma once

#include <cstdint>
#include <vector>

#include "mcpose/analysis/refine_floor.h"
#include "render/raster.h"

namespace mcpose::analysis {

// The start pose of instance `index`: `T_gt` moved by options.start_mm and turned by
// options.start_deg (about the model origin), directions drawn from (seed, index).
SE3 StartPose(const SE3& T_gt, const RefineFloorOptions& options, uint64_t index);

// One instance: `mesh` at `T_gt` in the observed `depth`, aligned in `box` from StartPose.
InstanceFloor AnalyzeInstance(const Intrinsics& K, const DepthImage& depth, const Mesh& mesh,
                              const std::vector<Eigen::Vector3f>& points, const SE3& T_gt,
                              const render::PixelRect& box, const RefineFloorOptions& options, uint64_t index);

}  // namespace mcpose::analysis

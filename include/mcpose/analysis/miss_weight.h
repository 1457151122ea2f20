// Misses: is a wrong answer the weight's fault or the search's? For an estimate far from the
// truth, the estimator's weight (at full resolution, every pixel of the full mesh, or as the
// filter weighs; colour where the estimate had it) of the estimate and of the truth aligned to
// the depth by the refinement, each at its best over the class's boxes. Where the truth weighs more, the filter never found
// it (a search failure: more samples or better moves could); where the estimate weighs as much
// or more, the weight itself prefers the wrong pose, and no search can fix it.
#pragma once

#include <span>
#include <vector>

#include "mcpose/camera.h"
#include "mcpose/detection.h"
#include "mcpose/image.h"
#include "mcpose/mesh.h"
#include "mcpose/analysis/scorer.h"
#include "mcpose/se3.h"
#include "mcpose/status.h"

namespace mcpose::analysis {

struct MissWeight {
  double estimate_weight = 0;  // the estimate's best weight over the boxes
  int estimate_box = -1;       // the box of that weight
  double truth_weight = 0;     // the aligned truth's, likewise
  int truth_box = -1;
  SE3 truth_aligned;           // the truth aligned in truth_box
  // How near the truth a sample must land to outweigh the estimate (in truth_box): the smallest
  // of kBasinSteps at which the aligned truth turned by that many degrees about a model axis
  // (through the mesh's bounding-box centre), or moved by that many millimetres along a camera
  // axis, weighs no more than the estimate; infinity where every such pose still weighs more, 0
  // for a weight failure. A narrow basin (a few degrees, a few millimetres) beside a broad wrong
  // pose is what makes a search failure hard to fix with more samples.
  double basin_turn_deg = 0;
  double basin_shift_mm = 0;
  bool search_failure() const { return truth_weight > estimate_weight; }
};

// The turns (degrees) and moves (millimetres) at which the basin is probed, smallest first.
inline constexpr double kBasinSteps[] = {2.5, 5, 10, 20};

// Weighs `T_est` and `T_gt` (aligned to `depth` in each box as the refinement aligns, with the
// scorer's refine options) in every box of `boxes` (one class) with `scorer`'s options, at full
// resolution or, `as_filter`, as the filter weighs its samples (its level of detail and pixel
// stride); `colour` may be null (depth only).
StatusOr<MissWeight> WeighMiss(Scorer& scorer, const Intrinsics& K, const DepthImage& depth,
                               const ColourImage* colour, const Mesh& mesh, std::span<const Detection> boxes,
                               const SE3& T_est, const SE3& T_gt, bool as_filter = false);

}  // namespace mcpose::analysis

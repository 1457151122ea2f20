// Twin margins: how surely the weight that resolves twins tells the right turn of an object from
// the wrong ones, one ground-truth instance at a time and without the search.
//
// Why: twin resolution (engine/twins.h) scores the filter's answer and its turns at full
// resolution, each aligned to the depth, and keeps the heaviest. Whether it keeps the right one
// is a property of the weight alone: run from the truth, it should rank the truth (and the turns
// close to it) above every turn far from it, in any light. This measures that directly, in a
// second or so per instance, where ADD(-S) over seeds mixes it with the search's luck.
//
// The candidates: TwinCandidates of the truth aligned to the depth (its 180-degree turns about
// the model axes, each turned about the model's most distinct axis in twin steps), each aligned
// to the depth by the twin resolution's steps, scored in the instance's visible-mask box. A
// candidate within `right_m` ADD(-S) of the truth is right, one beyond `wrong_m` wrong. The
// margin is the best right candidate's weight less the best wrong one's: positive, the weight
// decides right. The same for the weight's two parts alone: its depth part and its colour
// agreement.
#pragma once

#include <set>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "mcpose/analysis/scorer.h"
#include "mcpose/camera.h"
#include "mcpose/detection.h"
#include "mcpose/image.h"
#include "mcpose/mesh.h"
#include "mcpose/se3.h"
#include "mcpose/status.h"

namespace mcpose::analysis {

struct TwinMarginOptions {
  double right_m = 0.02;  // a candidate this close (ADD(-S)) to the truth is right
  double wrong_m = 0.04;  // one this far is wrong; in between neither
  bool IsValid(std::string* error) const;
};

struct TwinMargin {
  bool colour = false;       // the weight had its colour term
  int candidates = 0;
  int wrong = 0;             // candidates beyond wrong_m (none: the object has no twin here)
  double margin = 0;         // whole weight: best right - best wrong
  double depth_margin = 0;   // the weight's depth part alone
  double colour_margin = 0;  // the colour agreement alone (A', 0.5 neutral)
  int colour_pixels = 0;     // depth inliers of known colour of the best right candidate
};

// The margins of the instance at `T_gt` in `box`, weighed with `scorer`'s options at full
// resolution; `colour` may be null (depth only). `symmetric`: ADD-S rather than ADD between
// candidates and the truth.
StatusOr<TwinMargin> MeasureTwinMargin(Scorer& scorer, const Intrinsics& K, const DepthImage& depth,
                                       const ColourImage* colour, const Mesh& mesh, const Detection& box,
                                       const SE3& T_gt, std::span<const Eigen::Vector3f> points, bool symmetric,
                                       const TwinMarginOptions& options);

// Twin reach: from a wrong answer, do the twin candidates get back to the truth? The candidates
// of `T_est` (as twin resolution makes them, each aligned to the depth), weighed likewise: the
// one nearest the truth, how near, and whether it outweighs `T_est` itself.
struct TwinReach {
  double nearest_m = 0;        // ADD(-S) of the candidate nearest the truth
  double nearest_weight = 0;   // its weight
  double estimate_weight = 0;  // the answer's (candidate 0, unaligned)
  double best_weight = 0;      // the heaviest candidate's
  double best_m = 0;           // and its ADD(-S) to the truth
};

StatusOr<TwinReach> MeasureTwinReach(Scorer& scorer, const Intrinsics& K, const DepthImage& depth,
                                     const ColourImage* colour, const Mesh& mesh, const Detection& box,
                                     const SE3& T_est, const SE3& T_gt, std::span<const Eigen::Vector3f> points,
                                     bool symmetric);

}  // namespace mcpose::analysis

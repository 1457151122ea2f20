// Turn profiles: an engine's weight of the ground-truth pose turned about one model axis.
//
// Why: on the objects whose accuracy differs between engine options (the master chef can, the
// tuna can), the weight that tells the right turn from a wrong one differs by about 1e-3 (a
// weight is 0.6-0.9). A coarser render (a level of detail, a pixel stride) adds a jitter from
// one turn to the next that can be as large, and the filter then settles on a wrong turn more
// often. This measures both, deterministically and in about a second per instance, where
// ADD(-S) over seeds needs hours to show the same difference.
//
// The profile: T_gt turned about the model's bounding-box centre by k * step (k = 0 .. 360 /
// step - 1) about one model axis, each pose scored once in the box by the raster cores with the
// estimator's weight (options: engine, LOD, stride, inlier test, weight coefficients).
#pragma once

#include <span>
#include <string>
#include <vector>

#include "mcpose/camera.h"
#include "mcpose/detection.h"
#include "mcpose/image.h"
#include "mcpose/mesh.h"
#include "mcpose/options.h"
#include "mcpose/se3.h"
#include "mcpose/status.h"

namespace mcpose::analysis {

struct TurnProfileOptions {
  double step_deg = 5.0;   // turn step; must divide 360 into at least 8 steps
  int axis = -1;           // model axis 0, 1 or 2; -1: the one whose extent lies farthest from
                           // the mean of the other two (a can's axis)
  double near_deg = 10.0;  // turns within this of the truth count as the truth
  bool IsValid(std::string* error) const;
};

struct TurnProfileStats {
  // sqrt(mean((w[k+1] - 2 w[k] + w[k-1])^2) / 6), circular: for independent noise of standard
  // deviation s on a smooth profile this is about s.
  double jitter = 0;
  double range = 0;   // max - min of the profile smoothed over 7 steps (circular mean)
  double truth = 0;   // the highest weight within near_deg of the truth
  double beaten = 0;  // share of the turns beyond near_deg whose weight exceeds `truth`
};

// The statistics of a profile of weights at turns 0, step, 2 step, ... (circular).
TurnProfileStats SummarizeTurnProfile(std::span<const double> weights, double step_deg, double near_deg);


// The axis TurnProfileOptions::axis -1 picks: the model axis whose extent lies farthest from the
// mean of the other two (a can's axis; the twin candidates' axis).
int TurnAxis(const Mesh& mesh);

struct TurnProfile {
  int axis = 0;
  bool colour = false;       // the weight had its colour term
  double flip_weight[3] = {0, 0, 0};  // the truth turned 180 degrees about model x, y, z
  int triangles = 0;  // of the mesh (LOD level) the box renders
  int stride = 1;     // the box's pixel stride
  std::vector<double> angle_deg, weight;
  TurnProfileStats stats;
};

// The profile of `T_gt` of `mesh` in `box` of the observed `depth` (and `colour`, may be null),
// scored as the estimator with `options` scores (its threads, engine, level of detail, pixel
// stride, inlier test, weights, colour term), and the weights of the truth's three flips.
StatusOr<TurnProfile> ProfileTurns(const Intrinsics& K, const DepthImage& depth, const ColourImage* colour,
                                   const Mesh& mesh,
                                   const Detection& box, const SE3& T_gt, const EstimatorOptions& options,
                                   const TurnProfileOptions& turn);

}  // namespace mcpose::analysis

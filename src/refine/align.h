// Local refinement of a pose against the observed depth: projective point-to-plane alignment
// (the KinectFusion association) of the model's visible surface to the observed surface inside
// the box, with a robust loss, solved by damped Gauss-Newton steps on SE(3).
//
// The model's surface points are the pixels of the full mesh rendered at the pose (re-rendered
// every few steps as the pose moves); each is paired with the observed point at the pixel it
// projects to, and the residual is the distance along the observed surface's normal. Pairs
// whose observed surface lies in front of the model point (something else hides it, as the
// weight treats it) or farther than max_distance_m are left out; the rest are weighted by
// Tukey's biweight of their residual, so background and clutter near the object do not pull.
#pragma once

#include <vector>

#include "mcpose/camera.h"
#include "mcpose/image.h"
#include "mcpose/mesh.h"
#include "mcpose/se3.h"
#include "render/raster.h"

namespace mcpose::refine {

struct AlignOptions {
  int max_iterations = 20;
  int rerender_every = 5;         // steps between renders of the visible surface
  double tukey_m = 0.006;         // Tukey biweight scale: residuals beyond it weigh nothing
  double max_distance_m = 0.02;   // pairs farther apart than this are not paired
  double occlusion_m = 0.01;      // observed point in front of the model point by this: hidden
  int max_points = 3000;          // model points used per step (an even subsample)
  int min_points = 30;            // fewer pairs: stop
  double min_step = 1e-6;         // stop when the step (metres, radians) is below this
};

struct AlignResult {
  SE3 T_cam_obj;
  std::vector<SE3> path;      // the pose after each step (the last is T_cam_obj)
  int iterations = 0;
  int pairs = 0;              // pairs of the last step
  double rms_before_m = 0;    // robust RMS point-to-plane residual of the pairs, first step
  double rms_after_m = 0;     // the same after the last step
  bool moved = false;         // a step was taken
};

// Aligns `mesh` at `T0` to the observed `depth` inside `box` (image pixels, inside the image).
AlignResult AlignToDepth(const Intrinsics& K, const DepthImage& depth, const render::PixelRect& box, const Mesh& mesh,
                         const SE3& T0, const AlignOptions& options);

}  // namespace mcpose::refine

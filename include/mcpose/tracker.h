// The tracker: the estimator's particle filter run through a video. An object's first frame is
// estimated from its detections; each later frame starts from the previous frame's samples (the
// posterior), spread by a motion model, and runs a few iterations of the filter in a box around
// where the object was. When the answer no longer fits the observed depth (the object is hidden,
// moved fast or left the view) the track is lost, and the object is estimated afresh from that
// frame's detections.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <span>
#include <string>

#include "mcpose/camera.h"
#include "mcpose/dataset.h"
#include "mcpose/detection.h"
#include "mcpose/estimator.h"
#include "mcpose/image.h"
#include "mcpose/mesh.h"
#include "mcpose/options.h"
#include "mcpose/se3.h"
#include "mcpose/status.h"

namespace mcpose {

struct TrackerOptions {
  // First frames and re-initialisations: the single-frame estimator with these options; its
  // weight, engine, colour and refinement settings also score the tracked frames.
  EstimatorOptions estimator;
  int samples = 300;               // samples of a tracked frame, >= 1
  int iterations = 3;              // filter iterations of a tracked frame, >= 1
  double stop_weight = 0.9;        // a tracked frame stops early when its mean weight exceeds this
  // Motion model: each sample of the last posterior moves by Gaussian noise of these sizes
  // (translation in the camera frame, rotation about the object's origin) before the frame.
  double motion_sigma_t_m = 0.01;
  double motion_sigma_r_rad = 0.05;
  // The box a tracked frame scores in: the last pose's projected silhouette grown by this
  // fraction of its size on each side.
  double box_margin = 0.15;
  // Gauss-Newton steps of refinement in a tracked frame (the estimator's refine options
  // otherwise; none when refinement is off).
  int refine_iterations = 20;
  // The track is lost in a frame where its answer no longer fits the observed depth, judged on
  // every pixel of the full mesh at the answer (the weight itself is not comparable across
  // frames: the tracked box is not a detector's box, so N / N_b is not): lost when the share of
  // the rendered silhouette not hidden behind something nearer, (N_r - occluded) / N_r, is below
  // lost_visible, or when the share of that visible part which the depth confirms,
  // N / (N_r - occluded), is below lost_fit.
  double lost_fit = 0.4;
  double lost_visible = 0.1;

  bool IsValid(std::string* error) const;
};

// One object in one frame.
struct TrackStep {
  int obj_id = 0;
  SE3 T_cam_obj;
  double weight = 0;       // the best weight of the frame
  double fit = 0;          // N / (N_r - occluded) of the answer (TrackerOptions::lost_fit)
  double visible = 0;      // (N_r - occluded) / N_r of the answer (TrackerOptions::lost_visible)
  bool initialised = false;  // estimated from this frame's detections (first frame or re-initialised)
  bool lost = false;         // tracking lost the object in this frame (then re-initialised if it had boxes)
  int iterations = 0;        // filter iterations run in this frame
  Detection box;             // the box the answer was found in
  double ms = 0;             // wall time of this object in this frame
};

class Tracker {
 public:
  // Fails if the options are invalid (the message names the field).
  static StatusOr<std::unique_ptr<Tracker>> Create(const TrackerOptions& options);
  ~Tracker();

  // The pose of object class `obj_id` in the next frame of its track. `boxes` (this frame's
  // detections of the class) start the track and restart a lost one; they may be empty while it
  // holds. `colour` may be null. `stream_id` selects this frame's random streams (e.g. a hash of
  // frame and class): the result depends on the seed and the stream ids only, never on the
  // thread count.
  StatusOr<TrackStep> Track(const Intrinsics& K, const DepthImage& depth, const ColourImage* colour, const Mesh& mesh,
                            int obj_id, std::span<const Detection> boxes, uint64_t stream_id);

  // Forgets the track of `obj_id` (its next frame is estimated from its detections).
  void Reset(int obj_id);

  // The classes with a live track (their next frame needs no box), in increasing order.
  std::vector<int> TrackedIds() const;

  const TrackerOptions& options() const;

 private:
  struct Impl;
  explicit Tracker(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// One frame of a video, as `mcpose track` runs it: every class with a live track or with boxes in
// `boxes` (this frame's detections by obj_id), in increasing obj_id, each with the stream id the
// estimator gives (frame, class) (GroupStreamId). `meshes` holds a mesh for each such class.
// `load_colour` (may be null: depth only) is called once, only where the options use colour and
// one of the classes' meshes has it. Errors name the frame's class.
StatusOr<std::vector<TrackStep>> TrackFrame(Tracker& tracker, const Frame& frame,
                                            const std::map<int, const Mesh*>& meshes,
                                            const std::map<int, std::vector<Detection>>& boxes,
                                            const std::function<StatusOr<ColourImage>()>& load_colour);

}  // namespace mcpose

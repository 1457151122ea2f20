#include "mcpose/tracker.h"

#include "mcpose/option_table.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include "engine/box_scorer.h"
#include "engine/context.h"
#include "engine/estimate.h"
#include "engine/filter_loop.h"
#include "mcpose/option_table.h"
#include "mcpose/run.h"
#include "engine/refinement.h"
#include "score/inlier.h"
#include "track/motion.h"

namespace mcpose {

namespace {

// The estimator's options for a tracked frame: its samples and iterations, the finest noise
// from the start, colour at full weight from the start, no twin resolution (the track's twin
// was settled when it started).
EstimatorOptions TrackedFrameOptions(const TrackerOptions& t) {
  EstimatorOptions o = t.estimator;
  o.samples = t.samples;
  o.max_iterations = t.iterations;
  o.tau = t.stop_weight;
  o.diffusion.sigma_t_m = o.diffusion.sigma_t_min_m;
  o.diffusion.sigma_r_rad = o.diffusion.sigma_r_min_rad;
  o.diffusion.flip_rate = 0;
  o.appearance.ramp_iterations = 0;
  o.appearance.resolve_twins = false;
  o.refine.max_iterations = t.refine_iterations;
  if (t.refine_iterations == 0) o.refine.enabled = false;
  return o;
}

// The box around `mesh` at pose T: its projected bounds grown by `margin` of their size on each
// side, clipped to the image; empty when nothing of it is in front of the camera in the image.
Detection BoxAround(const Intrinsics& K, const Mesh& mesh, const SE3& T, double margin, const Detection& like) {
  double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
  for (const Eigen::Vector3f& v : mesh.vertices_m) {
    const Eigen::Vector3d c = T * v.cast<double>();
    if (!(c.z() > 0.05)) continue;
    const double u = K.fx * c.x() / c.z() + K.cx, w = K.fy * c.y() / c.z() + K.cy;
    x0 = std::min(x0, u), x1 = std::max(x1, u), y0 = std::min(y0, w), y1 = std::max(y1, w);
  }
  Detection d = like;
  if (!(x1 >= x0 && y1 >= y0)) {
    d.w = d.h = 0;
    return d;
  }
  const double mx = margin * (x1 - x0), my = margin * (y1 - y0);
  d.x = std::max(0.0, x0 - mx), d.y = std::max(0.0, y0 - my);
  d.w = std::min<double>(K.width, x1 + mx + 1) - d.x, d.h = std::min<double>(K.height, y1 + my + 1) - d.y;
  return d;
}

// How well pose T fits the observed depth, scored by `full` (one box, every pixel, the full
// mesh): `visible` is the share of the rendered silhouette not hidden behind something nearer,
// `fit` the share of that visible part that the observed depth confirms, N / (N_r - occluded).
// Both are 0 when nothing of the model is rendered in the box.
struct Fitness {
  double fit = 0, visible = 0;
};
Fitness FitOf(engine::BoxScorer& full, const SE3& T) {
  filter::ParticleSet one;
  one.Resize(1);
  one.R_cam_obj[0] = T.R, one.t_cam_obj_m[0] = T.t, one.box[0] = 0;
  score::InlierCounts c;
  EngineCounters unused;
  full.Count(one, std::span(&c, 1), &unused);
  Fitness f;
  const int32_t visible = c.rendered - c.occluded;
  if (c.rendered > 0) f.visible = static_cast<double>(visible) / c.rendered;
  if (visible > 0) f.fit = static_cast<double>(c.inliers) / visible;
  return f;
}

}  // namespace

bool TrackerOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = m;
    return false;
  };
  std::string inner;
  if (!estimator.IsValid(&inner)) return fail("estimator: " + inner);
  for (const TrackerOptionField& f : TrackerOptionFields())
    if (std::string problem = f.CheckBounds(*this); !problem.empty()) return fail(problem);
  return true;
}

struct Tracker::Impl {
  TrackerOptions options;
  EstimatorOptions frame_options;
  engine::Context first;    // first frames and re-initialisations
  engine::Context tracked;  // tracked frames
  struct Track {
    filter::ParticleSet posterior;  // the last frame's weighted samples
    SE3 pose;
    Detection box;                  // its box (the score carries into the tracked boxes)
  };
  std::map<int, Track> tracks;

  explicit Impl(const TrackerOptions& o)
      : options(o), frame_options(TrackedFrameOptions(o)), first(o.estimator), tracked(frame_options, first) {}

  // A fresh estimate from the frame's boxes.
  StatusOr<TrackStep> Start(const Intrinsics& K, const DepthImage& depth, const ColourImage* colour, const Mesh& mesh,
                            int obj_id, std::span<const Detection> boxes, uint64_t stream_id, TrackStep step) {
    Track track;
    MCPOSE_ASSIGN_OR_RETURN(ObjectEstimate e,
                            engine::EstimateObject(first, K, depth, colour, mesh, boxes, stream_id, &track.posterior));
    track.pose = e.T_cam_obj;
    track.box = boxes[static_cast<size_t>(e.best_box)];
    step.T_cam_obj = e.T_cam_obj;
    step.weight = e.best_weight;
    step.initialised = true;
    step.iterations += static_cast<int>(e.iterations.size());
    step.box = track.box;
    MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<engine::BoxScorer> full,
                            engine::BoxScorer::Create(first, K, depth, mesh, std::span(&step.box, 1), colour,
                                                      engine::Resolution::kFull));
    const Fitness f = FitOf(*full, step.T_cam_obj);
    step.fit = f.fit, step.visible = f.visible;
    tracks[obj_id] = std::move(track);
    return step;
  }
};

Tracker::Tracker(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Tracker::~Tracker() = default;

const TrackerOptions& Tracker::options() const { return impl_->options; }

void Tracker::Reset(int obj_id) { impl_->tracks.erase(obj_id); }

std::vector<int> Tracker::TrackedIds() const {
  std::vector<int> ids;
  for (const auto& [obj_id, track] : impl_->tracks) ids.push_back(obj_id);
  return ids;
}

StatusOr<std::unique_ptr<Tracker>> Tracker::Create(const TrackerOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) return InvalidArgument("invalid tracker options: " + error);
  MCPOSE_RETURN_IF_ERROR(engine::CheckSimdTarget(options.estimator.engine));
  return std::unique_ptr<Tracker>(new Tracker(std::make_unique<Impl>(options)));
}

StatusOr<TrackStep> Tracker::Track(const Intrinsics& K, const DepthImage& depth, const ColourImage* colour,
                                   const Mesh& mesh, int obj_id, std::span<const Detection> boxes, uint64_t stream_id) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  Impl& im = *impl_;
  const engine::SimdScopeGuard simd(im.tracked);
  TrackStep step;
  step.obj_id = obj_id;
  auto done = [&](StatusOr<TrackStep> s) {
    if (s.ok()) s->ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    return s;
  };
  auto it = im.tracks.find(obj_id);
  if (it == im.tracks.end()) {
    if (boxes.empty())
      return InvalidArgument("obj_id " + std::to_string(obj_id) + ": no track yet and no box to start one");
    return done(im.Start(K, depth, colour, mesh, obj_id, boxes, stream_id, step));
  }
  Impl::Track& track = it->second;

  // ---- The box around where the object was; the posterior moved by the motion model -------
  const Detection box = BoxAround(K, mesh, track.pose, im.options.box_margin, track.box);
  bool lost = engine::ClipBox(box.x, box.y, box.w, box.h, K.width, K.height).empty();
  if (!lost) {
    const EstimatorOptions& o = im.frame_options;
    const track::MotionModel motion{im.options.motion_sigma_t_m, im.options.motion_sigma_r_rad,
                                    o.resample.cdf_table_size};
    filter::ParticleSet samples = track::PredictSamples(track.posterior, motion, o.samples, o.seed, stream_id);

    // ---- A few iterations of the filter in that box, then refinement --------------------------
    MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<engine::BoxScorer> scorer,
                            engine::BoxScorer::Create(im.tracked, K, depth, mesh, std::span(&box, 1), colour));
    filter::ParticleSet posterior;
    ObjectEstimate e = engine::RunFilter(
        *scorer, o, im.tracked.pool(), stream_id,
        [&posterior](int, const filter::ParticleSet& weighted) { posterior = weighted; }, &samples);
    step.iterations = static_cast<int>(e.iterations.size());
    const SE3 filtered = e.T_cam_obj;
    MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<engine::BoxScorer> full,
                            engine::BoxScorer::Create(im.tracked, K, depth, mesh, std::span(&box, 1),
                                                      scorer->uses_colour() ? colour : nullptr,
                                                      engine::Resolution::kFull));
    if (o.refine.enabled) e = engine::RefineEstimate(o.refine, *full, depth, std::move(e));
    step.T_cam_obj = e.T_cam_obj, step.weight = e.best_weight, step.box = box;
    const Fitness f = FitOf(*full, e.T_cam_obj);
    step.fit = f.fit, step.visible = f.visible;
    lost = step.fit < im.options.lost_fit || step.visible < im.options.lost_visible;
    if (!lost) {
      engine::MoveSamples(filtered, e.T_cam_obj, &posterior);
      track.posterior = std::move(posterior);
      track.pose = e.T_cam_obj;
      return done(step);
    }
  }

  // ---- Lost: estimated afresh from this frame's boxes, if it has some -----------------------
  step.lost = true;
  if (boxes.empty()) {  // nothing to start again from: the last pose, and no track
    if (!(step.box.w > 0)) step.T_cam_obj = track.pose;
    im.tracks.erase(it);
    return done(step);
  }
  return done(im.Start(K, depth, colour, mesh, obj_id, boxes, stream_id, step));
}

StatusOr<std::vector<TrackStep>> TrackFrame(Tracker& tracker, const Frame& frame,
                                            const std::map<int, const Mesh*>& meshes,
                                            const std::map<int, std::vector<Detection>>& boxes,
                                            const std::function<StatusOr<ColourImage>()>& load_colour) {
  std::set<int> classes;
  for (int obj_id : tracker.TrackedIds()) classes.insert(obj_id);
  for (const auto& [obj_id, dets] : boxes) classes.insert(obj_id);
  bool wants_colour = false;
  for (int obj_id : classes) {
    auto it = meshes.find(obj_id);
    if (it == meshes.end() || it->second == nullptr)
      return InvalidArgument("obj_id " + std::to_string(obj_id) + ": no mesh given for a class of the frame");
    wants_colour |= !it->second->appearance.empty();
  }
  std::optional<ColourImage> colour;
  if (load_colour && wants_colour && tracker.options().estimator.appearance.enabled) {
    MCPOSE_ASSIGN_OR_RETURN(colour, load_colour());
  }
  static const std::vector<Detection> kNoBoxes;
  std::vector<TrackStep> steps;
  for (int obj_id : classes) {
    auto b = boxes.find(obj_id);
    const std::vector<Detection>& dets = b == boxes.end() ? kNoBoxes : b->second;
    StatusOr<TrackStep> step =
        tracker.Track(frame.K, frame.depth, colour ? &*colour : nullptr, *meshes.at(obj_id), obj_id, dets,
                      GroupStreamId(frame.key.scene_id, frame.key.image_id, obj_id));
    if (!step.ok())
      return Status(step.status().code(), "obj_id " + std::to_string(obj_id) + ": " + step.status().message());
    steps.push_back(std::move(step).value());
  }
  return steps;
}

}  // namespace mcpose

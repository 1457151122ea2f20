#include "mcpose/analysis/turn_profile.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include <Eigen/Geometry>

#include "engine/box_scorer.h"
#include "engine/context.h"
#include "engine/twins.h"

namespace mcpose::analysis {

bool TurnProfileOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = m;
    return false;
  };
  if (!(step_deg > 0 && step_deg <= 45)) return fail("step_deg must be in (0, 45]");
  const double steps = 360.0 / step_deg;
  if (std::fabs(steps - std::round(steps)) > 1e-9) return fail("step_deg must divide 360");
  if (axis < -1 || axis > 2) return fail("axis must be 0, 1, 2 or -1 (automatic)");
  if (!(near_deg >= 0 && near_deg < 180)) return fail("near_deg must be in [0, 180)");
  return true;
}

TurnProfileStats SummarizeTurnProfile(std::span<const double> w, double step_deg, double near_deg) {
  TurnProfileStats s;
  const int n = static_cast<int>(w.size());
  if (n < 3) return s;
  auto at = [&](int k) { return w[static_cast<size_t>(((k % n) + n) % n)]; };
  double sq = 0;
  for (int k = 0; k < n; ++k) {
    const double d2 = at(k + 1) - 2 * at(k) + at(k - 1);
    sq += d2 * d2;
  }
  s.jitter = std::sqrt(sq / n / 6);
  double lo = INFINITY, hi = -INFINITY;
  for (int k = 0; k < n; ++k) {
    double m = 0;
    for (int j = -3; j <= 3; ++j) m += at(k + j);
    lo = std::min(lo, m / 7), hi = std::max(hi, m / 7);
  }
  s.range = hi - lo;
  auto is_near = [&](int k) {
    const double a = std::fmod(k * step_deg, 360.0);
    return std::min(a, 360.0 - a) <= near_deg + 1e-9;
  };
  s.truth = -INFINITY;
  for (int k = 0; k < n; ++k)
    if (is_near(k)) s.truth = std::max(s.truth, w[static_cast<size_t>(k)]);
  int far = 0, beaten = 0;
  for (int k = 0; k < n; ++k) {
    if (is_near(k)) continue;
    ++far;
    beaten += w[static_cast<size_t>(k)] > s.truth;
  }
  s.beaten = far > 0 ? static_cast<double>(beaten) / far : 0.0;
  return s;
}

StatusOr<TurnProfile> ProfileTurns(const Intrinsics& K, const DepthImage& depth, const ColourImage* colour,
                                   const Mesh& mesh,
                                   const Detection& box, const SE3& T_gt, const EstimatorOptions& options,
                                   const TurnProfileOptions& turn) {
  std::string error;
  if (!turn.IsValid(&error)) return InvalidArgument("invalid turn profile options: " + error);
  if (!options.IsValid(&error)) return InvalidArgument("invalid engine options: " + error);
  // The estimator's scorer for this box: its engine, mesh level, stride and weight.
  engine::Context context(options);
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<engine::BoxScorer> scorer,
                          engine::BoxScorer::Create(context, K, depth, mesh, std::span(&box, 1), colour));
  TurnProfile out;
  out.axis = turn.axis >= 0 ? turn.axis : engine::DistinctAxis(mesh);
  out.stride = scorer->box_observation(0).stride;
  out.colour = scorer->uses_colour();
  out.triangles = static_cast<int>(scorer->box_mesh(0).triangles.size());

  const int n = static_cast<int>(std::lround(360.0 / turn.step_deg));
  const Eigen::Vector3d c = (0.5f * (mesh.BoundsMin() + mesh.BoundsMax())).cast<double>();
  filter::ParticleSet poses;
  poses.Resize(static_cast<size_t>(n + 3));
  for (int k = 0; k < n; ++k) {
    const double a = k * turn.step_deg;
    const Eigen::Matrix3d S =
        Eigen::AngleAxisd(a * std::numbers::pi / 180, Eigen::Vector3d::Unit(out.axis)).toRotationMatrix();
    // Turned about the box centre c: X -> S (X - c) + c in the model frame.
    poses.R_cam_obj[static_cast<size_t>(k)] = T_gt.R * S;
    poses.t_cam_obj_m[static_cast<size_t>(k)] = T_gt.R * (c - S * c) + T_gt.t;
    poses.box[static_cast<size_t>(k)] = 0;
    out.angle_deg.push_back(a);
  }
  for (int f = 0; f < 3; ++f) {  // the flips: diag(+-1), -1 off the axis
    Eigen::Vector3d d(-1, -1, -1);
    d[f] = 1;
    const Eigen::Matrix3d F = d.asDiagonal();
    poses.R_cam_obj[static_cast<size_t>(n + f)] = T_gt.R * F;
    poses.t_cam_obj_m[static_cast<size_t>(n + f)] = T_gt.R * (c - F * c) + T_gt.t;
    poses.box[static_cast<size_t>(n + f)] = 0;
  }
  EngineCounters counters;
  scorer->Weigh(&poses, &counters);
  out.weight.assign(poses.weight.begin(), poses.weight.begin() + n);
  for (int f = 0; f < 3; ++f) out.flip_weight[f] = poses.weight[static_cast<size_t>(n + f)];
  out.stats = SummarizeTurnProfile(out.weight, turn.step_deg, turn.near_deg);
  return out;
}

int TurnAxis(const Mesh& mesh) { return engine::DistinctAxis(mesh); }

}  // namespace mcpose::analysis

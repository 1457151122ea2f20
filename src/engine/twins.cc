#include "engine/twins.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <numeric>

#include <Eigen/Geometry>

#include "core/rng.h"
#include "filter/diffuse.h"
#include "engine/filter_loop.h"
#include "engine/refinement.h"
#include "score/weight.h"

namespace mcpose::engine {

namespace {

// Substream of the refinement's starting samples.
constexpr uint64_t kTwinStream = 0x7715;
// Candidates aligned to the depth before the final comparison: the best by their first score.
constexpr int kAlignedCandidates = 8;

}  // namespace

int DistinctAxis(const Mesh& mesh) {
  const Eigen::Vector3f e = mesh.BoundsMax() - mesh.BoundsMin();
  int axis = 0;
  double best = -1;
  for (int a = 0; a < 3; ++a) {
    const double off = std::fabs(e[a] - 0.5 * (e[(a + 1) % 3] + e[(a + 2) % 3]));
    if (off > best) best = off, axis = a;
  }
  return axis;
}

std::vector<SE3> TwinCandidates(const SE3& T, const Mesh& mesh, double step_deg) {
  const Eigen::Vector3d c = (0.5f * (mesh.BoundsMin() + mesh.BoundsMax())).cast<double>();
  const int axis = DistinctAxis(mesh);
  const int steps = static_cast<int>(std::lround(360.0 / step_deg));
  std::vector<SE3> out;
  std::vector<Eigen::Matrix3d> turns;
  for (int f = -1; f < 3; ++f) {
    Eigen::Vector3d d(1, 1, 1);
    if (f >= 0) d = Eigen::Vector3d(-1, -1, -1), d[f] = 1;
    const Eigen::Matrix3d F = d.asDiagonal();
    for (int k = 0; k < steps; ++k) {
      const Eigen::Matrix3d S =
          Eigen::AngleAxisd(k * step_deg * std::numbers::pi / 180, Eigen::Vector3d::Unit(axis)).toRotationMatrix();
      // X -> S F (X - c) + c in the model frame, then T.
      const Eigen::Matrix3d M = S * F;
      // A flip about the distinct axis is a half turn about it, and a flip about a third axis
      // a flip about the second turned half round: with a step that divides 180 degrees, two of
      // the four families repeat the other two. Each turn is kept once.
      const bool repeated = std::any_of(turns.begin(), turns.end(), [&](const Eigen::Matrix3d& m) {
        return (m - M).cwiseAbs().maxCoeff() < 1e-9;
      });
      if (repeated) continue;
      turns.push_back(M);
      out.emplace_back(T.R * M, T.R * (c - M * c) + T.t);
    }
  }
  return out;
}

ObjectEstimate ResolveTwins(Context& context, BoxScorer& scorer, BoxScorer& full, const DepthImage& depth,
                            ObjectEstimate filtered, uint64_t stream_id) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const EstimatorOptions& opt = context.options();
  const AppearanceOptions& a = opt.appearance;
  const int box = filtered.best_box;

  // ---- Every candidate scored on every pixel of the full mesh; the best few aligned to the
  // depth (refine/align.h) and scored again: a twin's best place can lie a little off the
  // candidate (a curved object turned about its box centre) --------------------------------
  std::vector<SE3> candidates = TwinCandidates(filtered.T_cam_obj, scorer.mesh(), a.twin_step_deg);
  filter::ParticleSet poses;
  auto score = [&] {
    poses.Resize(candidates.size());
    for (size_t i = 0; i < candidates.size(); ++i) {
      poses.R_cam_obj[i] = candidates[i].R, poses.t_cam_obj_m[i] = candidates[i].t, poses.box[i] = 0;
    }
    EngineCounters counters;
    full.Weigh(&poses, &counters);
  };
  score();
  if (opt.refine.enabled && opt.refine.twin_iterations > 0) {
    std::vector<size_t> order(candidates.size());
    std::iota(order.begin(), order.end(), size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](size_t x, size_t y) { return poses.weight[x] > poses.weight[y]; });
    order.resize(std::min(order.size(), static_cast<size_t>(kAlignedCandidates)));
    const refine::AlignOptions align = AlignSettings(opt.refine, opt.refine.twin_iterations);
    const render::PixelRect rect = full.box_observation(0).image_rect;
    context.pool().ParallelFor(static_cast<int64_t>(order.size()), [&](int64_t begin, int64_t end, int) {
      for (int64_t k = begin; k < end; ++k) {
        SE3& c = candidates[order[static_cast<size_t>(k)]];
        c = refine::AlignToDepth(scorer.K(), depth, rect, scorer.mesh(), c, align).T_cam_obj;
      }
    });
    score();
  }
  size_t winner = 0;
  for (size_t i = 1; i < poses.size(); ++i)
    if (poses.weight[i] > poses.weight[winner]) winner = i;  // ties: the earlier candidate
  if (a.twin_depth_margin > 0) {
    const std::span<const score::InlierCounts> counts = full.last_counts();
    std::vector<double> depth_weight(poses.size());
    double best_depth = -1;
    for (size_t i = 0; i < poses.size(); ++i) {
      depth_weight[i] = score::Weight(counts[i], full.box_observation(0).score, opt.weight);
      best_depth = std::max(best_depth, depth_weight[i]);
    }
    double best_colour = -1;
    for (size_t i = 0; i < poses.size(); ++i) {
      if (depth_weight[i] < best_depth - a.twin_depth_margin) continue;
      const double colour = score::VisibleColourAgreement(counts[i], a);
      if (colour > best_colour) best_colour = colour, winner = i;
    }
  }
  double runner_up = -1;
  for (size_t i = 0; i < poses.size(); ++i)
    if (i != winner) runner_up = std::max(runner_up, poses.weight[i]);

  TwinRecord record;
  record.ran = true;
  record.candidates = static_cast<int>(candidates.size());
  record.winner = static_cast<int>(winner);
  record.winner_weight = poses.weight[winner];
  record.margin = poses.weight[winner] - runner_up;

  // ---- Refine the winner: a short filter run from samples around it at the finest noise ----
  ObjectEstimate result = std::move(filtered);
  if (a.twin_refine_iterations > 0) {
    EstimatorOptions refine = opt;
    refine.max_iterations = a.twin_refine_iterations;
    refine.diffusion.sigma_t_m = opt.diffusion.sigma_t_min_m;
    refine.diffusion.sigma_r_rad = opt.diffusion.sigma_r_min_rad;
    refine.diffusion.flip_rate = 0;
    refine.appearance.ramp_iterations = 0;
    filter::ParticleSet start;
    start.Resize(static_cast<size_t>(opt.samples));
    for (int i = 0; i < opt.samples; ++i) {
      Rng rng(opt.seed, stream_id, kTwinStream, static_cast<uint64_t>(i));
      start.box[i] = box;
      if (i == 0) {  // the winner itself is one of the samples
        start.R_cam_obj[i] = candidates[winner].R, start.t_cam_obj_m[i] = candidates[winner].t;
        continue;
      }
      filter::Diffuse(candidates[winner].R, candidates[winner].t, refine.diffusion.sigma_r_rad,
                      refine.diffusion.sigma_t_m, rng, &start.R_cam_obj[i], &start.t_cam_obj_m[i]);
    }
    const ObjectEstimate refined =
        RunFilter(scorer, refine, context.pool(), HashCombine(stream_id, kTwinStream), {}, &start);
    result.T_cam_obj = refined.T_cam_obj;
    result.best_weight = refined.best_weight;
    record.refine_iterations = static_cast<int>(refined.iterations.size());
    for (const IterationSummary& it : refined.iterations) result.iterations.push_back(it);
  } else {
    result.T_cam_obj = candidates[winner];
  }
  record.ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  result.twins = record;
  return result;
}

}  // namespace mcpose::engine

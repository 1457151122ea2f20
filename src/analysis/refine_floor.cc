#include "mcpose/analysis/refine_floor.h"
#include "analysis/refine_floor_instance.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "mcpose/analysis/visible_instances.h"
#include "core/rng.h"
#include "engine/refinement.h"
#include "mcpose/eval.h"

namespace mcpose::analysis {

namespace {

// Substream of the random start directions.
constexpr uint64_t kStartStream = 0x5f100;

Eigen::Vector3d RandomDirection(Rng& rng) {
  Eigen::Vector3d v;
  do {
    v = Eigen::Vector3d(rng.Normal(), rng.Normal(), rng.Normal());
  } while (!(v.norm() > 1e-9));
  return v.normalized();
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

bool RefineFloorOptions::IsValid(std::string* error) const {
  auto fail = [error](const char* what) {
    if (error) *error = what;
    return false;
  };
  if (!(std::isfinite(start_mm) && start_mm >= 0)) return fail("start_mm must be >= 0");
  if (!(std::isfinite(start_deg) && start_deg >= 0 && start_deg <= 180)) return fail("start_deg must be in [0, 180]");
  if (!(std::isfinite(box_margin) && box_margin >= 0)) return fail("box_margin must be >= 0");
  if (!(std::isfinite(auc_max_m) && auc_max_m > 0)) return fail("auc_max_m must be > 0");
  if (refine.max_iterations < 0) return fail("the alignment's iterations must be >= 0");
  if (!(std::isfinite(refine.tukey_m) && refine.tukey_m > 0)) return fail("the alignment's Tukey scale must be > 0");
  if (!(std::isfinite(refine.max_distance_m) && refine.max_distance_m > 0))
    return fail("the alignment's pairing distance must be > 0");
  return true;
}

SE3 StartPose(const SE3& T_gt, const RefineFloorOptions& options, uint64_t index) {
  Rng rng(options.seed, kStartStream, 0, index);
  const Eigen::Vector3d axis = RandomDirection(rng), move = RandomDirection(rng);
  const Eigen::Matrix3d turn = ExpSO3(axis * (options.start_deg * std::numbers::pi / 180));
  return SE3(turn * T_gt.R, T_gt.t + move * (options.start_mm / 1000));
}

InstanceFloor AnalyzeInstance(const Intrinsics& K, const DepthImage& depth, const Mesh& mesh,
                              const std::vector<Eigen::Vector3f>& points, const SE3& T_gt,
                              const render::PixelRect& box, const RefineFloorOptions& options, uint64_t index) {
  InstanceFloor out;
  const SE3 start = StartPose(T_gt, options, index);
  const refine::AlignResult aligned = refine::AlignToDepth(
      K, depth, box, mesh, start, engine::AlignSettings(options.refine, options.refine.max_iterations));
  out.adds_start_m = AddS(points, start, T_gt);
  out.adds_aligned_m = AddS(points, aligned.T_cam_obj, T_gt);
  out.iterations = aligned.iterations;
  const Eigen::Vector3d d = aligned.T_cam_obj.t - T_gt.t, ray = T_gt.t.normalized();
  out.along_ray_mm = 1000 * d.dot(ray);
  out.across_ray_mm = 1000 * (d - d.dot(ray) * ray).norm();
  return out;
}

StatusOr<RefineFloorReport> AnalyzeRefineFloor(const Dataset& dataset, const RefineFloorOptions& options,
                                               void (*progress)(int done, int total)) {
  std::string error;
  if (!options.IsValid(&error)) return InvalidArgument("invalid refine-floor options: " + error);
  RefineFloorReport report;
  // The synthetic frames are rendered from their truth: they agree with it by construction.
  MCPOSE_RETURN_IF_ERROR(ForEachVisibleInstance(
      dataset, /*real_only=*/true,
      [&](const VisibleInstance& v) {
        const Detection& t = v.tight;
        const double mx = options.box_margin * t.w, my = options.box_margin * t.h;
        const render::PixelRect box{std::max(0, static_cast<int>(std::floor(t.x - mx))),
                                    std::max(0, static_cast<int>(std::floor(t.y - my))),
                                    std::min(v.frame.K.width, static_cast<int>(std::ceil(t.x + t.w + mx))),
                                    std::min(v.frame.K.height, static_cast<int>(std::ceil(t.y + t.h + my)))};
        InstanceFloor f = AnalyzeInstance(v.frame.K, v.frame.depth, v.mesh, v.points, v.gt.T_cam_obj, box, options,
                                          report.instances.size());
        f.key = v.frame.key;
        f.obj_id = v.gt.obj_id;
        report.instances.push_back(f);
        return Status::Ok();
      },
      progress));
  std::map<int, std::vector<const InstanceFloor*>> by_object;
  for (const InstanceFloor& f : report.instances) by_object[f.obj_id].push_back(&f);
  auto summarize = [&](const std::vector<const InstanceFloor*>& group, RefineFloorReport::Row* r) {
    std::vector<double> aligned_mm, aligned_m;
    for (const InstanceFloor* f : group) {
      r->mean_start_mm += 1000 * f->adds_start_m;
      r->mean_across_ray_mm += f->across_ray_mm;
      aligned_mm.push_back(1000 * f->adds_aligned_m);
      aligned_m.push_back(f->adds_aligned_m);
    }
    r->instances = static_cast<int>(group.size());
    if (group.empty()) return;
    for (double a : aligned_mm) r->mean_aligned_mm += a;
    r->mean_start_mm /= r->instances, r->mean_across_ray_mm /= r->instances, r->mean_aligned_mm /= r->instances;
    r->median_aligned_mm = Median(aligned_mm);
    r->auc = AccuracyAuc(aligned_m, options.auc_max_m);
  };
  std::vector<const InstanceFloor*> all;
  for (const InstanceFloor& f : report.instances) all.push_back(&f);
  for (const auto& [id, group] : by_object) {
    RefineFloorReport::Row& r = report.per_object.emplace_back();
    r.obj_id = id;
    r.name = dataset.ObjectName(id);
    summarize(group, &r);
  }
  report.overall.name = "ALL";
  summarize(all, &report.overall);
  return report;
}

}  // namespace mcpose::analysis

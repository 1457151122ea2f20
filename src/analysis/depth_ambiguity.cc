#include "mcpose/analysis/depth_ambiguity.h"
#include "analysis/ambiguity_instance.h"

#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <set>

#include <Eigen/Geometry>

#include "mcpose/analysis/visible_instances.h"
#include "mcpose/eval.h"

namespace mcpose::analysis {

bool AmbiguityOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = m;
    return false;
  };
  if (!(step_deg > 0 && step_deg <= 180)) return fail("step_deg must be in (0, 180]");
  if (!(agree_eps_m > 0 && std::isfinite(agree_eps_m))) return fail("agree_eps_m must be > 0");
  if (!(min_agreement > 0 && min_agreement <= 1)) return fail("min_agreement must be in (0, 1]");
  if (!(occlusion_eps_m > 0 && std::isfinite(occlusion_eps_m))) return fail("occlusion_eps_m must be > 0");
  if (!(threshold_m > 0 && std::isfinite(threshold_m))) return fail("threshold_m must be > 0");
  return true;
}

std::vector<Eigen::Matrix3d> CandidateRotations(double step_deg) {
  const double pi = std::numbers::pi;
  const std::array<Eigen::Matrix3d, 4> flips = {
      Eigen::Matrix3d::Identity(), Eigen::AngleAxisd(pi, Eigen::Vector3d::UnitX()).toRotationMatrix(),
      Eigen::AngleAxisd(pi, Eigen::Vector3d::UnitY()).toRotationMatrix(),
      Eigen::AngleAxisd(pi, Eigen::Vector3d::UnitZ()).toRotationMatrix()};
  const int steps = static_cast<int>(std::floor(360.0 / step_deg + 1e-9));
  std::vector<Eigen::Matrix3d> out;
  auto add = [&](const Eigen::Matrix3d& S) {
    for (const auto& r : out)
      if ((r - S).norm() < 1e-6) return;
    out.push_back(S);
  };
  for (const auto& F : flips) {
    for (int axis = 0; axis < 3; ++axis) {
      for (int k = 0; k < steps; ++k) {
        add(Eigen::AngleAxisd(k * step_deg * pi / 180.0, Eigen::Vector3d::Unit(axis)).toRotationMatrix() * F);
      }
    }
  }
  return out;
}

namespace {

std::vector<float> RenderBox(const Intrinsics& K, const Mesh& mesh, const SE3& T, const render::PixelRect& box) {
  render::RasterParams p;
  p.fx = static_cast<float>(K.fx);
  p.fy = static_cast<float>(K.fy);
  p.cx = static_cast<float>(K.cx);
  p.cy = static_cast<float>(K.cy);
  p.box = box;
  std::vector<render::ScreenVertex> v(mesh.vertices_m.size());
  render::ProjectVertices(mesh.vertices_m, T.R.cast<float>(), T.t.cast<float>(), p, v);
  std::vector<float> z(static_cast<size_t>(box.area()), INFINITY);
  RasterCounters stats;
  render::RasterizeDepthReference(v, mesh.triangles, p, z.data(), &stats);
  return z;
}

}  // namespace

InstanceAmbiguity AnalyzeInstance(const Intrinsics& K, const DepthImage& depth, const Mesh& mesh,
                                  const std::vector<Eigen::Vector3f>& points, const SE3& T_gt,
                                  const render::PixelRect& box, bool symmetric,
                                  const AmbiguityOptions& options) {
  InstanceAmbiguity out;
  const std::vector<float> gt = RenderBox(K, mesh, T_gt, box);
  const Eigen::Vector3d c = (0.5f * (mesh.BoundsMin() + mesh.BoundsMax())).cast<double>();
  const float agree = static_cast<float>(options.agree_eps_m);
  const float occl = static_cast<float>(options.occlusion_eps_m);
  for (const Eigen::Matrix3d& S : CandidateRotations(options.step_deg)) {
    // Turned about the box centre c: X -> S (X - c) + c in the model frame.
    const SE3 T(T_gt.R * S, T_gt.R * (c - S * c) + T_gt.t);
    ++out.candidates;
    const std::vector<float> cand = RenderBox(K, mesh, T, box);
    int64_t compared = 0, agreeing = 0;
    for (int y = box.y0; y < box.y1; ++y) {
      for (int x = box.x0; x < box.x1; ++x) {
        const size_t i = static_cast<size_t>(y - box.y0) * box.width() + (x - box.x0);
        const float zg = gt[i], zc = cand[i];
        if (!std::isfinite(zg) && !std::isfinite(zc)) continue;
        const float obs = depth.depth_m[static_cast<size_t>(y) * depth.width + x];
        if (obs > 0 && obs < std::min(zg, zc) - occl) continue;  // hidden for both
        ++compared;
        if (std::isfinite(zg) && std::isfinite(zc) && std::fabs(zg - zc) < agree) ++agreeing;
      }
    }
    const bool equivalent = compared == 0 || agreeing >= options.min_agreement * static_cast<double>(compared);
    if (!equivalent) continue;
    ++out.equivalent;
    const double err = symmetric ? AddS(points, T, T_gt) : Add(points, T, T_gt);
    if (err < options.threshold_m) ++out.equivalent_correct;
  }
  out.ceiling = out.equivalent > 0 ? static_cast<double>(out.equivalent_correct) / out.equivalent : 0.0;
  return out;
}

StatusOr<AmbiguityReport> AnalyzeDataset(const Dataset& dataset, const AmbiguityOptions& options,
                                         void (*progress)(int done, int total)) {
  std::string error;
  if (!options.IsValid(&error)) return InvalidArgument("invalid ambiguity options: " + error);
  const std::set<int> symmetric = YcbvSymmetricObjectIds();
  AmbiguityReport report;
  MCPOSE_RETURN_IF_ERROR(ForEachVisibleInstance(
      dataset, /*real_only=*/false,
      [&](const VisibleInstance& v) {
        const render::PixelRect box{static_cast<int>(v.tight.x), static_cast<int>(v.tight.y),
                                    static_cast<int>(v.tight.x + v.tight.w), static_cast<int>(v.tight.y + v.tight.h)};
        InstanceAmbiguity a = AnalyzeInstance(v.frame.K, v.frame.depth, v.mesh, v.points, v.gt.T_cam_obj, box,
                                              symmetric.count(v.gt.obj_id) > 0, options);
        a.key = v.frame.key;
        a.obj_id = v.gt.obj_id;
        report.instances.push_back(a);
        return Status::Ok();
      },
      progress));
  std::map<int, AmbiguityReport::Row> rows;
  for (const InstanceAmbiguity& a : report.instances) {
    for (AmbiguityReport::Row* r : {&rows[a.obj_id], &report.overall}) {
      ++r->instances;
      r->mean_equivalent += a.equivalent;
      r->ceiling += a.ceiling;
    }
  }
  report.overall.name = "ALL";
  for (auto& [id, r] : rows) {
    r.obj_id = id;
    r.name = dataset.ObjectName(id);
    report.per_object.push_back(r);
  }
  for (auto& r : report.per_object) {
    r.mean_equivalent /= r.instances;
    r.ceiling /= r.instances;
  }
  if (report.overall.instances > 0) {
    report.overall.mean_equivalent /= report.overall.instances;
    report.overall.ceiling /= report.overall.instances;
  }
  return report;
}

}  // namespace mcpose::analysis

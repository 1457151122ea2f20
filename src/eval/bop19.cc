// The BOP19 metrics (VSD, MSSD, MSPD) and their average recall. The definitions follow
// bop_toolkit's (pose_error.py, visibility.py, misc.py, pose_matching.py, score.py,
// scripts/eval_calc_errors.py and eval_calc_scores.py); the comments say where mcpose's
// conventions enter (pixel centres at integer coordinates, its own renderer).

#include "mcpose/bop19.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <set>

#include "render/depth_image.h"

namespace mcpose {
namespace {

// The rotation by `angle` about the unit vector `axis`.
Eigen::Matrix3d Turn(const Eigen::Vector3d& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis).toRotationMatrix();
}

// The ground-truth pose of each symmetric look: T_gt S.
std::vector<SE3> SymmetricTruths(const SE3& T_gt, const std::vector<SE3>& symmetries) {
  std::vector<SE3> out;
  out.reserve(symmetries.size());
  for (const SE3& S : symmetries) out.push_back(T_gt * S);
  return out;
}

// A depth image as distances from the camera centre (0 stays 0), pixel (x, y) at (x, y).
std::vector<float> Distances(const DepthImage& depth, const Intrinsics& K) {
  std::vector<float> out(depth.depth_m.size());
  for (int y = 0; y < depth.height; ++y)
    for (int x = 0; x < depth.width; ++x) {
      const double u = (x - K.cx) / K.fx, v = (y - K.cy) / K.fy;
      const size_t i = static_cast<size_t>(y) * depth.width + x;
      out[i] = static_cast<float>(depth.depth_m[i] * std::sqrt(u * u + v * v + 1));
    }
  return out;
}

// Whether the images of two balls of radius r centred at t_a and t_b overlap (bop_toolkit's
// overlapping_sphere_projections): VSD renders only then.
bool SphereProjectionsOverlap(double radius_m, const Eigen::Vector3d& t_a, const Eigen::Vector3d& t_b) {
  if (t_a.z() == 0 || t_b.z() == 0) return false;
  const Eigen::Vector2d a(t_a.x() / t_a.z(), t_a.y() / t_a.z()), b(t_b.x() / t_b.z(), t_b.y() / t_b.z());
  return (a - b).norm() < radius_m * (1 / t_a.z() + 1 / t_b.z());
}

}  // namespace

std::vector<SE3> SymmetryTransformations(const ModelInfo& info, double max_sym_disc_step) {
  std::vector<SE3> discrete = {SE3()};
  discrete.insert(discrete.end(), info.discrete.begin(), info.discrete.end());
  std::vector<SE3> continuous;
  for (const ContinuousSymmetry& c : info.continuous) {
    const int n = static_cast<int>(std::ceil(M_PI / max_sym_disc_step));
    for (int i = 0; i < n; ++i) {
      const Eigen::Matrix3d R = Turn(c.axis, 2 * M_PI * i / n);
      continuous.emplace_back(R, c.offset_m - R * c.offset_m);
    }
  }
  if (continuous.empty()) return discrete;
  std::vector<SE3> out;
  out.reserve(discrete.size() * continuous.size());
  for (const SE3& c : continuous)
    for (const SE3& d : discrete) out.push_back(c * d);
  return out;
}

double Mssd(const std::vector<Eigen::Vector3f>& points_m, const SE3& T_est, const SE3& T_gt,
            const std::vector<SE3>& symmetries) {
  double best = std::numeric_limits<double>::infinity();
  for (const SE3& T_sym : SymmetricTruths(T_gt, symmetries)) {
    double worst = 0;
    for (const Eigen::Vector3f& p : points_m) {
      const Eigen::Vector3d x = p.cast<double>();
      worst = std::max(worst, (T_est * x - T_sym * x).norm());
      if (worst >= best) break;  // this symmetry cannot win
    }
    best = std::min(best, worst);
  }
  return best;
}

double Mspd(const std::vector<Eigen::Vector3f>& points_m, const SE3& T_est, const SE3& T_gt,
            const std::vector<SE3>& symmetries, const Intrinsics& K) {
  const auto project = [&](const Eigen::Vector3d& c) {
    return Eigen::Vector2d(K.fx * c.x() / c.z() + K.cx, K.fy * c.y() / c.z() + K.cy);
  };
  std::vector<Eigen::Vector2d> est;
  est.reserve(points_m.size());
  for (const Eigen::Vector3f& p : points_m) est.push_back(project(T_est * p.cast<double>()));
  double best = std::numeric_limits<double>::infinity();
  for (const SE3& T_sym : SymmetricTruths(T_gt, symmetries)) {
    double worst = 0;
    for (size_t i = 0; i < points_m.size(); ++i) {
      worst = std::max(worst, (est[i] - project(T_sym * points_m[i].cast<double>())).norm());
      if (worst >= best) break;
    }
    best = std::min(best, worst);
  }
  return best;
}

std::vector<double> Vsd(const DepthImage& test_depth, const Intrinsics& K, const Mesh& mesh, const SE3& T_est,
                        const SE3& T_gt, double diameter_m, double delta_m, const std::vector<double>& taus) {
  std::vector<double> errors(taus.size(), 1.0);
  if (!SphereProjectionsOverlap(diameter_m / 2, T_est.t, T_gt.t)) return errors;
  const std::vector<float> test = Distances(test_depth, K);
  const std::vector<float> est = Distances(render::RenderDepth(mesh, T_est, K), K);
  const std::vector<float> gt = Distances(render::RenderDepth(mesh, T_gt, K), K);
  // BOP19 visibility: a rendered pixel at most delta behind the test surface, or where the test
  // image has no depth.
  const auto visible = [&](float rendered, float observed) {
    return rendered > 0 && (rendered - observed <= static_cast<float>(delta_m) || observed == 0);
  };
  std::vector<float> differences;  // |gt - est| / diameter on the intersection
  int64_t union_pixels = 0;
  for (size_t i = 0; i < test.size(); ++i) {
    const bool in_gt = visible(gt[i], test[i]);
    const bool in_est = visible(est[i], test[i]) || (in_gt && est[i] > 0);
    if (!in_gt && !in_est) continue;
    ++union_pixels;
    if (in_gt && in_est) differences.push_back(static_cast<float>(std::abs(gt[i] - est[i]) / diameter_m));
  }
  if (union_pixels == 0) return errors;
  const int64_t outside_intersection = union_pixels - static_cast<int64_t>(differences.size());
  for (size_t k = 0; k < taus.size(); ++k) {
    int64_t wrong = outside_intersection;
    for (float d : differences) wrong += d >= taus[k];
    errors[k] = static_cast<double>(wrong) / static_cast<double>(union_pixels);
  }
  return errors;
}

Bop19Summary Bop19Recalls(const std::vector<const Bop19Instance*>& instances, const Bop19Options& options) {
  Bop19Summary s;
  // Groups of one (image, object): matching happens within a group.
  std::map<std::pair<FrameKey, int>, std::vector<const Bop19Instance*>> groups;
  for (const Bop19Instance* i : instances) {
    groups[{i->key, i->obj_id}].push_back(i);
    s.targets += i->valid;
  }
  if (s.targets == 0) return s;
  // Matched valid instances under one error test, over every group.
  const auto matched = [&](const std::function<bool(const Bop19Errors&, const Bop19Instance&, double*)>& error_below) {
    int count = 0;
    for (const auto& [key, members] : groups) {
      const size_t estimates = members.front()->errors.size();
      std::vector<bool> taken(members.size(), false);
      for (size_t e = 0; e < estimates; ++e) {
        int best = -1;
        double best_error = 0;
        for (size_t g = 0; g < members.size(); ++g) {
          double error = 0;
          if (taken[g] || !members[g]->valid || !error_below(members[g]->errors[e], *members[g], &error)) continue;
          if (best < 0 || error < best_error) best = static_cast<int>(g), best_error = error;
        }
        if (best >= 0) taken[static_cast<size_t>(best)] = true, ++count;
      }
    }
    return count;
  };
  const double targets = s.targets;
  // The recall averaged over `thresholds`, an estimate's error against an instance by `error_of`.
  const auto mean_recall = [&](const std::vector<double>& thresholds, const auto& error_of) {
    double sum = 0;
    for (double th : thresholds)
      sum += matched([&](const Bop19Errors& e, const Bop19Instance& i, double* error) {
               *error = error_of(e, i);
               return *error < th;
             }) / targets;
    return sum / static_cast<double>(thresholds.size());
  };
  s.ar_vsd = 0;
  for (size_t tau = 0; tau < options.vsd_taus.size(); ++tau)
    s.ar_vsd += mean_recall(options.vsd_thresholds, [tau](const Bop19Errors& e, const Bop19Instance&) { return e.vsd[tau]; });
  s.ar_vsd /= static_cast<double>(options.vsd_taus.size());
  s.ar_mssd = mean_recall(options.mssd_thresholds,
                          [](const Bop19Errors& e, const Bop19Instance& i) { return e.mssd_m / i.diameter_m; });
  s.ar_mspd = mean_recall(options.mspd_thresholds_px, [](const Bop19Errors& e, const Bop19Instance& i) {
    return e.mspd_px * 640.0 / i.image_width;
  });
  s.ar = (s.ar_vsd + s.ar_mssd + s.ar_mspd) / 3;
  return s;
}

StatusOr<Bop19Report> EvaluateBop19(const Dataset& dataset, const std::vector<PoseResult>& results,
                                    const std::map<int, ModelInfo>& models_info,
                                    const std::vector<Bop19Target>* targets, const Bop19Options& options,
                                    const std::set<FrameKey>* only) {
  // inst_count per (image, object), from the targets or from the visible fractions below.
  std::map<std::pair<FrameKey, int>, int> inst_count;
  std::set<FrameKey> frames;
  if (targets != nullptr) {
    for (const Bop19Target& t : *targets) {
      inst_count[{t.key, t.obj_id}] = t.inst_count;
      frames.insert(t.key);
    }
    const std::vector<FrameKey> all = dataset.Frames();
    const std::set<FrameKey> known(all.begin(), all.end());
    for (const FrameKey& k : frames)
      if (!known.contains(k))
        return NotFound("a target names scene_id " + std::to_string(k.scene_id) + ", im_id " +
                        std::to_string(k.image_id) + ", which " + dataset.root() + " does not hold");
  } else {
    for (const FrameKey& k : dataset.Frames()) frames.insert(k);
  }
  if (only != nullptr) std::erase_if(frames, [&](const FrameKey& k) { return !only->contains(k); });
  // The rows of each (image, object), best score first; ties keep the file's order.
  std::map<std::pair<FrameKey, int>, std::vector<const PoseResult*>> rows;
  for (const PoseResult& r : results) rows[{FrameKey{r.scene_id, r.im_id}, r.obj_id}].push_back(&r);
  for (auto& [key, list] : rows)
    std::stable_sort(list.begin(), list.end(), [](const PoseResult* a, const PoseResult* b) { return a->score > b->score; });

  Bop19Report report;
  std::map<int, Mesh> meshes;
  std::map<int, std::vector<SE3>> symmetries;
  for (const FrameKey& key : frames) {
    MCPOSE_ASSIGN_OR_RETURN(const Frame frame, dataset.LoadFrame(key));
    std::vector<Bop19Instance> image;
    for (const GtInstance& gt : frame.gt) {
      const auto info = models_info.find(gt.obj_id);
      if (info == models_info.end())
        return NotFound("the models information has no obj_id " + std::to_string(gt.obj_id) + " (" +
                        dataset.ObjectName(gt.obj_id) + ")");
      if (!meshes.count(gt.obj_id)) {
        MCPOSE_ASSIGN_OR_RETURN(Mesh mesh, dataset.LoadMesh(gt.obj_id));
        meshes.emplace(gt.obj_id, std::move(mesh));
        symmetries.emplace(gt.obj_id, SymmetryTransformations(info->second, options.max_sym_disc_step));
      }
      Bop19Instance i;
      i.key = key, i.obj_id = gt.obj_id, i.gt_index = gt.gt_index;
      i.diameter_m = info->second.diameter_m, i.image_width = frame.K.width;
      MCPOSE_ASSIGN_OR_RETURN(const MaskImage mask, dataset.LoadVisibleMask(key, gt));
      const DepthImage silhouette = render::RenderDepth(meshes.at(gt.obj_id), gt.T_cam_obj, frame.K);
      int64_t visible = 0, all = 0;
      for (uint8_t v : mask.values) visible += v != 0;
      for (float z : silhouette.depth_m) all += z > 0;
      i.visible_fraction = all > 0 ? std::min(1.0, static_cast<double>(visible) / static_cast<double>(all)) : 0.0;
      image.push_back(std::move(i));
    }
    if (targets == nullptr)
      for (const Bop19Instance& i : image)
        if (i.visible_fraction >= options.min_visible_fraction) ++inst_count[{key, i.obj_id}];
    // Valid: the inst_count most visible instances of each target object (ties: lower index).
    std::vector<size_t> order(image.size());
    std::iota(order.begin(), order.end(), size_t{0});
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return image[a].visible_fraction > image[b].visible_fraction; });
    std::map<int, int> slots;
    for (const Bop19Instance& i : image) {
      const auto c = inst_count.find({key, i.obj_id});
      slots[i.obj_id] = c == inst_count.end() ? 0 : c->second;
    }
    for (size_t k : order)
      if (slots[image[k].obj_id] > 0) image[k].valid = true, --slots[image[k].obj_id];
    // Errors of the inst_count best rows of each target object against each of its instances.
    for (Bop19Instance& i : image) {
      const auto c = inst_count.find({key, i.obj_id});
      const auto r = rows.find({key, i.obj_id});
      if (c == inst_count.end() || r == rows.end()) continue;
      const size_t n = std::min(r->second.size(), static_cast<size_t>(c->second));
      const GtInstance& gt = frame.gt[static_cast<size_t>(&i - image.data())];
      const std::vector<Eigen::Vector3f>& points = meshes.at(i.obj_id).vertices_m;
      for (size_t e = 0; e < n; ++e) {
        const SE3& T_est = r->second[e]->T_cam_obj;
        Bop19Errors errors;
        errors.vsd = Vsd(frame.depth, frame.K, meshes.at(i.obj_id), T_est, gt.T_cam_obj, i.diameter_m,
                         options.vsd_delta_m, options.vsd_taus);
        errors.mssd_m = (T_est.t - gt.T_cam_obj.t).norm() >= i.diameter_m
                            ? std::numeric_limits<double>::infinity()
                            : Mssd(points, T_est, gt.T_cam_obj, symmetries.at(i.obj_id));
        errors.mspd_px = Mspd(points, T_est, gt.T_cam_obj, symmetries.at(i.obj_id), frame.K);
        i.errors.push_back(std::move(errors));
      }
    }
    for (Bop19Instance& i : image) report.instances.push_back(std::move(i));
  }

  // Every instance takes part in the matching (an invalid one matches nothing); the recalls
  // count the valid ones. Objects without a target get no row.
  std::map<int, std::vector<const Bop19Instance*>> by_object;
  std::vector<const Bop19Instance*> all;
  for (const Bop19Instance& i : report.instances) {
    by_object[i.obj_id].push_back(&i);
    all.push_back(&i);
  }
  for (const auto& [obj_id, members] : by_object) {
    Bop19Summary s = Bop19Recalls(members, options);
    if (s.targets == 0) continue;
    s.obj_id = obj_id;
    s.name = dataset.ObjectName(obj_id);
    report.per_object.push_back(s);
  }
  report.overall = Bop19Recalls(all, options);
  report.overall.name = "ALL";
  return report;
}

}  // namespace mcpose

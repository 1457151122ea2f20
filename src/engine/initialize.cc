#include "engine/initialize.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <vector>

#include "core/check.h"
#include "core/rng.h"
#include "engine/box_scorer.h"

namespace mcpose::engine {

namespace {

constexpr uint64_t kInitStream = 0xA11CE;

// The `q` quantile of the valid depths of a box, or 0 if it has none.
double DepthQuantile(const std::vector<float>& observed, double q) {
  std::vector<float> valid;
  valid.reserve(observed.size());
  for (float d : observed)
    if (d > 0.f) valid.push_back(d);
  if (valid.empty()) return 0.0;
  const size_t k = std::min(valid.size() - 1, static_cast<size_t>(q * (valid.size() - 1) + 0.5));
  std::nth_element(valid.begin(), valid.begin() + k, valid.end());
  return valid[k];
}

// Places a turned model on the ray through its box centre with its nearest point at a given
// depth, from the model's vertices (at most kMaxVertices of them, evenly strided) about their
// bounding-box centre.
class FrontPlacer {
 public:
  explicit FrontPlacer(const Mesh& mesh) : centre_(0.5f * (mesh.BoundsMin() + mesh.BoundsMax()).cast<double>()) {
    const size_t n = mesh.vertices_m.size();
    const size_t stride = std::max<size_t>(1, (n + kMaxVertices - 1) / kMaxVertices);
    for (size_t v = 0; v < n; v += stride) offsets_.push_back(mesh.vertices_m[v].cast<double>() - centre_);
  }

  // The translation that puts the bounding-box centre of the model turned by `R` on `ray` (its
  // z component 1) with its nearest vertex at depth z_front.
  Eigen::Vector3d Translation(const Eigen::Matrix3d& R, const Eigen::Vector3d& ray, double z_front) const {
    const Eigen::RowVector3d view_row = R.row(2);
    double nearest = 0;
    for (const Eigen::Vector3d& o : offsets_) nearest = std::min(nearest, view_row.dot(o));
    return ray * (z_front - nearest) - R * centre_;
  }

 private:
  static constexpr size_t kMaxVertices = 1024;
  Eigen::Vector3d centre_;
  std::vector<Eigen::Vector3d> offsets_;
};

}  // namespace

double InitialDepth(const Intrinsics& K, const Mesh& mesh, const Detection& d, const score::BoxObservation& box,
                    double depth_quantile) {
  const Eigen::Vector3f size = mesh.BoundsMax() - mesh.BoundsMin();
  std::array<float, 3> sides = {size.x(), size.y(), size.z()};
  std::sort(sides.begin(), sides.end());
  const double z = DepthQuantile(box.observed, depth_quantile);
  if (z > 0) return z + 0.5 * sides[1];
  return std::max(K.fx, K.fy) * size.norm() / std::max(1.0, std::hypot(d.w, d.h));
}

int SelectLodLevel(const render::LodChain& lod, const Intrinsics& K, const Mesh& mesh, const Detection& d,
                   const score::BoxObservation& box, const EstimatorOptions& options) {
  if (!(options.engine.lod_error_px > 0)) return 0;
  const double z = InitialDepth(K, mesh, d, box, options.init.depth_quantile);
  return lod.Select(render::LodErrorBudgetM(static_cast<float>(options.engine.lod_error_px), static_cast<float>(z),
                                            static_cast<float>(std::min(K.fx, K.fy))));
}

void InitializeSamples(const BoxScorer& scorer, const EstimatorOptions& options, uint64_t stream_id,
                       filter::ParticleSet* particles) {
  const Intrinsics& K = scorer.K();
  const int n = options.samples;
  std::vector<double> scores;
  for (int b = 0; b < scorer.num_boxes(); ++b) scores.push_back(std::max(scorer.detection(b).score, 1e-6));
  const std::vector<int> per_box = filter::AllocateSamples(scores, n);

  const double share = options.init.front_share;
  std::optional<FrontPlacer> front;
  if (share > 0) front.emplace(scorer.mesh());
  filter::ParticleSet& p = *particles;
  p.Resize(n);
  int i = 0;
  for (int b = 0; b < scorer.num_boxes(); ++b) {
    const Detection& d = scorer.detection(b);
    const score::BoxObservation& box = scorer.box_observation(b);
    const double z = InitialDepth(K, scorer.mesh(), d, box, options.init.depth_quantile);
    // The front depth needs valid depth in the box; without it every sample starts at `z`.
    const double z_front = front ? DepthQuantile(box.observed, options.init.front_quantile) : 0.0;
    const double uc = d.x + 0.5 * d.w, vc = d.y + 0.5 * d.h;
    const Eigen::Vector3d ray((uc - K.cx) / K.fx, (vc - K.cy) / K.fy, 1.0);
    for (int k = 0; k < per_box[static_cast<size_t>(b)]; ++k, ++i) {
      Rng rng(options.seed, stream_id, kInitStream, static_cast<uint64_t>(i));
      p.box[i] = static_cast<int32_t>(b);
      p.R_cam_obj[i] = filter::UniformRotation(rng.Uniform(), rng.Uniform(), rng.Uniform());
      // Sample k of the box starts at the front depth when (k + 1) share passes an integer:
      // every sample at share 1, every other one at 0.5, none at 0.
      const bool at_front = z_front > 0 && std::floor((k + 1) * share) > std::floor(k * share);
      const Eigen::Vector3d t = at_front ? front->Translation(p.R_cam_obj[i], ray, z_front) : Eigen::Vector3d(ray * z);
      p.t_cam_obj_m[i] = t + options.init.sigma_t_m * Eigen::Vector3d(rng.Normal(), rng.Normal(), rng.Normal());
    }
  }
  MCPOSE_CHECK_EQ(i, n);
}

}  // namespace mcpose::engine

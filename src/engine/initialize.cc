#include "engine/initialize.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "core/check.h"
#include "core/rng.h"
#include "engine/box_scorer.h"
#include "engine/context.h"

namespace mcpose::engine {

namespace {

constexpr uint64_t kInitStream = 0xA11CE;
constexpr uint64_t kPlaneStream = 0x91A4E;

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

// A model at rest on `plane`: one of its rest faces drawn by area, turned at random about the
// plane's normal, its centre of mass above the plane where `ray` (z component 1) meets that
// height. Sets *R_cam_obj; returns the translation.
Eigen::Vector3d PoseAtRest(const MeshRests& rests, const SupportPlane& plane, const Eigen::Vector3d& ray, Rng& rng,
                         Eigen::Matrix3d* R_cam_obj) {
  const double u = rng.Uniform();
  const size_t r = std::min<size_t>(
      static_cast<size_t>(std::upper_bound(rests.area_cdf.begin(), rests.area_cdf.end(), u) - rests.area_cdf.begin()),
      rests.rests.size() - 1);
  const mcpose::RestPose& rest = rests.rests[r];
  // The table frame in the camera: z the plane's normal, x any direction in the plane.
  const Eigen::Vector3d z_axis = plane.normal;
  const Eigen::Vector3d helper = std::fabs(z_axis.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d x_axis = (helper - helper.dot(z_axis) * z_axis).normalized();
  Eigen::Matrix3d R_cam_table;
  R_cam_table.col(0) = x_axis, R_cam_table.col(1) = z_axis.cross(x_axis), R_cam_table.col(2) = z_axis;
  const double yaw = rng.Uniform(0, 2 * std::numbers::pi);
  *R_cam_obj = R_cam_table * Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * rest.R;
  // The centre of mass at s ray, rest.height above the plane: n . (s ray) + offset = height.
  const double along = plane.normal.dot(ray);
  const double s = std::fabs(along) > 1e-6 ? (rest.height - plane.offset) / along : 0.0;
  const Eigen::Vector3d com_cam = s > 0 ? Eigen::Vector3d(s * ray) : Eigen::Vector3d(ray);
  return com_cam - *R_cam_obj * rests.centre_of_mass;
}

}  // namespace

std::optional<SupportPlane> FindSupportPlane(const DepthImage& depth, const Intrinsics& K, const Detection& d,
                                             uint64_t seed, uint64_t stream_id, int box_index) {
  // The ring: the box grown by half its size on each side, the box itself left out; at most
  // about 3000 points, evenly strided.
  const render::PixelRect inner = ClipBox(d.x, d.y, d.w, d.h, depth.width, depth.height);
  const render::PixelRect outer = ClipBox(d.x - 0.5 * d.w, d.y - 0.5 * d.h, 2 * d.w, 2 * d.h, depth.width, depth.height);
  const int64_t area = static_cast<int64_t>(outer.x1 - outer.x0) * (outer.y1 - outer.y0);
  const int step = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(area) / 3000.0)));
  std::vector<Eigen::Vector3d> ring, inside;
  for (int y = outer.y0; y < outer.y1; y += step)
    for (int x = outer.x0; x < outer.x1; x += step) {
      const float z = depth.at(x, y);
      if (!(z > 0.f)) continue;
      const Eigen::Vector3d p((x - K.cx) / K.fx * z, (y - K.cy) / K.fy * z, z);
      const bool in_box = x >= inner.x0 && x < inner.x1 && y >= inner.y0 && y < inner.y1;
      (in_box ? inside : ring).push_back(p);
    }
  if (ring.size() < 50 || inside.empty()) return std::nullopt;
  Rng rng(seed, stream_id, kPlaneStream, static_cast<uint64_t>(box_index));
  SupportPlane best;
  size_t best_inliers = 0;
  for (int iteration = 0; iteration < 200; ++iteration) {
    const Eigen::Vector3d& a = ring[rng.NextU64() % ring.size()];
    const Eigen::Vector3d& b = ring[rng.NextU64() % ring.size()];
    const Eigen::Vector3d& c = ring[rng.NextU64() % ring.size()];
    Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() < 1e-9) continue;
    n.normalize();
    if (n.dot(a) > 0) n = -n;  // towards the camera
    const double offset = -n.dot(a);
    size_t inliers = 0;
    for (const Eigen::Vector3d& p : ring) inliers += std::fabs(n.dot(p) + offset) < kPlaneInlierM;
    if (inliers > best_inliers) best_inliers = inliers, best = SupportPlane{n, offset, 0};
  }
  // A support plane holds a good part of the ring, and the box's points do not lie behind it (an
  // object thinner than kPlaneInlierM may lie within it).
  if (best_inliers < ring.size() * 3 / 10) return std::nullopt;
  std::vector<double> heights;
  for (const Eigen::Vector3d& p : inside) heights.push_back(best.normal.dot(p) + best.offset);
  std::nth_element(heights.begin(), heights.begin() + heights.size() / 2, heights.end());
  if (heights[heights.size() / 2] < -0.5 * kPlaneInlierM) return std::nullopt;
  best.share = static_cast<double>(best_inliers) / static_cast<double>(ring.size());
  return best;
}

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
                       filter::ParticleSet* particles, int count) {
  const Intrinsics& K = scorer.K();
  const int n = count >= 0 ? count : options.samples;
  std::vector<double> scores;
  for (int b = 0; b < scorer.num_boxes(); ++b) scores.push_back(std::max(scorer.detection(b).score, 1e-6));
  const std::vector<int> per_box = filter::AllocateSamples(scores, n);

  const double share = options.init.front_share;
  std::optional<FrontPlacer> front;
  if (share > 0) front.emplace(scorer.mesh());
  const double rest_share = options.init.rest_share;
  const MeshRests* rests = rest_share > 0 ? scorer.rests() : nullptr;
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
    const std::optional<SupportPlane> plane =
        rests ? FindSupportPlane(scorer.depth(), K, d, options.seed, stream_id, b) : std::nullopt;
    // Sample k of the box starts at the front depth when (k + 1) share passes an integer: every
    // sample at share 1, every other one at 0.5, none at 0. Rest samples are taken from the
    // centre samples first (the front ones find thin objects before a table), evenly among them
    // by the same rule, and only past 1 - share from the front ones.
    const double front_share = z_front > 0 ? share : 0.0;
    const double rest_of_centre = front_share < 1 ? std::min(1.0, rest_share / (1 - front_share)) : 0.0;
    const double rest_of_front = front_share > 0 ? std::max(0.0, rest_share - (1 - front_share)) / front_share : 0.0;
    const auto passes = [](int k, double rate) { return std::floor((k + 1) * rate) > std::floor(k * rate); };
    int fronts = 0, centres = 0;
    for (int k = 0; k < per_box[static_cast<size_t>(b)]; ++k, ++i) {
      Rng rng(options.seed, stream_id, kInitStream, static_cast<uint64_t>(i));
      p.box[i] = static_cast<int32_t>(b);
      p.R_cam_obj[i] = filter::UniformRotation(rng.Uniform(), rng.Uniform(), rng.Uniform());
      const bool at_front = passes(k, front_share);
      const bool at_rest = plane && (at_front ? passes(fronts, rest_of_front) : passes(centres, rest_of_centre));
      (at_front ? fronts : centres) += 1;
      Eigen::Vector3d t;
      if (at_rest) {
        // The ray through a random point of the box's central `spread` share: the row's offset
        // drawn first, then the column's (two statements, so the order is the same with every
        // compiler).
        const double spread = options.init.rest_spread;
        Eigen::Vector3d rest_ray = ray;
        if (spread > 0) {
          const double dv = (rng.Uniform() - 0.5) * spread * d.h;
          const double du = (rng.Uniform() - 0.5) * spread * d.w;
          rest_ray = Eigen::Vector3d((uc + du - K.cx) / K.fx, (vc + dv - K.cy) / K.fy, 1.0);
        }
        t = PoseAtRest(*rests, *plane, rest_ray, rng, &p.R_cam_obj[i]);
      } else {
        t = at_front ? front->Translation(p.R_cam_obj[i], ray, z_front) : Eigen::Vector3d(ray * z);
      }
      p.t_cam_obj_m[i] = t + options.init.sigma_t_m * Eigen::Vector3d(rng.Normal(), rng.Normal(), rng.Normal());
    }
  }
  MCPOSE_CHECK_EQ(i, n);
}

}  // namespace mcpose::engine

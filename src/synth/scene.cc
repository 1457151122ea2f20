#include "mcpose/synth_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Geometry>

#include "score/colour_grid.h"
#include "core/rng.h"
#include "render/raster.h"
#include "render/surface_distance.h"
#include "mcpose/photometric.h"
#include "core/rest_pose.h"

namespace mcpose::synth {

namespace {

constexpr uint64_t kSceneStream = 0x5c3e, kDepthStream = 0xde97, kColourStream = 0xc010;
constexpr double kDeg = std::numbers::pi / 180;

// The colour of a black body of `kelvin` as linear-light gains (the largest 1), after Tanner
// Helland's fit of the sRGB white points of 1,000-40,000 K.
Eigen::Vector3d LightColour(double kelvin) {
  const double t = kelvin / 100;
  double r, g, b;
  if (t <= 66) {
    r = 255;
    g = 99.4708025861 * std::log(t) - 161.1195681661;
    b = t <= 19 ? 0 : 138.5177312231 * std::log(t - 10) - 305.0447927307;
  } else {
    r = 329.698727446 * std::pow(t - 60, -0.1332047592);
    g = 288.1221695283 * std::pow(t - 60, -0.0755148492);
    b = 255;
  }
  Eigen::Vector3d c;
  const double s[3] = {r, g, b};
  for (int i = 0; i < 3; ++i) c[i] = SrgbToLinear(static_cast<uint8_t>(std::clamp(s[i], 0.0, 255.0)));
  return c / c.maxCoeff();
}

// Point p on triangle (a, b, c) nearest to q, as barycentric coordinates (Ericson's
// closest-point-on-triangle, by Voronoi regions).
Eigen::Vector3f Barycentric(const Eigen::Vector3f& q, const Eigen::Vector3f& a, const Eigen::Vector3f& b,
                            const Eigen::Vector3f& c) {
  const Eigen::Vector3f ab = b - a, ac = c - a, ap = q - a;
  const float d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return {1, 0, 0};
  const Eigen::Vector3f bp = q - b;
  const float d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return {0, 1, 0};
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const float v = d1 / (d1 - d3);
    return {1 - v, v, 0};
  }
  const Eigen::Vector3f cp = q - c;
  const float d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return {0, 0, 1};
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const float w = d2 / (d2 - d6);
    return {1 - w, 0, w};
  }
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const float w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0, 1 - w, w};
  }
  const float denom = 1 / (va + vb + vc);
  const float v = vb * denom, w = vc * denom;
  return {1 - v - w, v, w};
}

struct Placed {
  size_t model = 0;
  SE3 T_cam_obj;
  Rgba8 plain;  // the colour of a model without colour of its own
};

}  // namespace

// What the maker keeps of each model: its stable rest poses and a grid for finding the surface
// point a pixel shows (built when the model is first shown).
struct SceneMaker::Model {
  int obj_id = 0;
  const Mesh* mesh = nullptr;
  Eigen::Vector3d com;
  std::vector<RestPose> rests;
  std::unique_ptr<render::TriangleGrid> grid;
};

SceneMaker::~SceneMaker() = default;

StatusOr<std::unique_ptr<SceneMaker>> SceneMaker::Create(std::vector<SceneObject> objects, const SceneOptions& o,
                                                         uint64_t seed) {
  std::string error;
  if (!o.IsValid(&error)) return InvalidArgument("synthetic scene options: " + error);
  if (objects.empty()) return InvalidArgument("no model to place");
  std::unique_ptr<SceneMaker> maker(new SceneMaker);
  maker->options_ = o;
  maker->seed_ = seed;
  maker->models_.resize(objects.size());
  for (size_t m = 0; m < objects.size(); ++m) {
    Model& p = maker->models_[m];
    p.obj_id = objects[m].obj_id;
    p.mesh = objects[m].mesh;
    p.com = CentreOfMass(*p.mesh);
    auto rests = StableRestPoses(*p.mesh);
    if (!rests.ok()) return InvalidArgument("model of obj_id " + std::to_string(p.obj_id) + ": " + rests.status().message());
    p.rests = std::move(*rests);
    if (p.rests.empty()) return InvalidArgument("model of obj_id " + std::to_string(p.obj_id) + " has no stable rest pose");
  }
  return maker;
}

bool SceneOptions::IsValid(std::string* error) const {
  const auto fail = [error](const std::string& m) {
    if (error) *error = m;
    return false;
  };
  std::string k;
  if (!camera.IsValid(&k)) return fail("camera: " + k);
  if (min_objects < 1 || max_objects < min_objects || max_objects > 32)
    return fail("need 1 <= min_objects <= max_objects <= 32");
  if (copies < 1 || copies > 8) return fail("copies must lie in [1, 8], got " + std::to_string(copies));
  if (!(min_distance_m >= 0.2 && max_distance_m > min_distance_m && max_distance_m <= 5))
    return fail("need 0.2 <= min_distance_m < max_distance_m <= 5");
  if (!(side_share >= 0 && side_share <= 1)) return fail("side_share must lie in [0, 1]");
  if (!(min_visible >= 0 && min_visible < 1)) return fail("min_visible must lie in [0, 1)");
  if (!(depth_noise >= 0 && depth_noise <= 0.05)) return fail("depth_noise must lie in [0, 0.05]");
  if (!(depth_offset_m >= 0 && depth_offset_m <= 0.05)) return fail("depth_offset_m must lie in [0, 0.05]");
  if (!(grazing_deg > 0 && grazing_deg <= 90)) return fail("grazing_deg must lie in (0, 90]");
  if (!(edge_dropout >= 0 && edge_dropout <= 1)) return fail("edge_dropout must lie in [0, 1]");
  if (!(max_range_m > max_distance_m && max_range_m <= 6.5)) return fail("max_range_m must lie in (max_distance_m, 6.5]");
  if (!(colour_noise >= 0 && colour_noise <= 64)) return fail("colour_noise must lie in [0, 64]");
  if (jpeg_quality < 0 || jpeg_quality > 100) return fail("jpeg_quality must lie in [0, 100]");
  return true;
}

std::vector<uint16_t> MeasureDepth(const std::vector<float>& depth_m, const std::vector<Eigen::Vector3f>& normals,
                                   const Intrinsics& K, const SceneOptions& o, uint64_t seed) {
  const int w = K.width, h = K.height;
  std::vector<uint16_t> out(static_cast<size_t>(w) * h, 0);
  Rng frame_rng(seed, kDepthStream);
  const double offset = frame_rng.Uniform(-o.depth_offset_m, o.depth_offset_m);
  const double cos_grazing = std::cos(o.grazing_deg * kDeg);
  for (int y = 0; y < h; ++y) {
    Rng rng(seed, kDepthStream, static_cast<uint64_t>(y) + 1);
    for (int x = 0; x < w; ++x) {
      const size_t i = static_cast<size_t>(y) * w + x;
      const float z = depth_m[i];
      // Draw every pixel's numbers, measured or not, so one pixel's fate does not move another's.
      const double noise = rng.Normal(), drop = rng.Uniform();
      if (!std::isfinite(z) || z <= 0 || z > o.max_range_m) continue;
      const Eigen::Vector3f ray = Eigen::Vector3f((x - K.cx) / K.fx, (y - K.cy) / K.fy, 1).normalized();
      if (std::fabs(normals[i].dot(ray)) < cos_grazing) continue;
      bool edge = false;
      for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}}) {
        const int xx = x + dx, yy = y + dy;
        if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
        const float n = depth_m[static_cast<size_t>(yy) * w + xx];
        edge |= !(std::fabs(n - z) < 0.01f);
      }
      if (edge && drop < o.edge_dropout) continue;
      const double measured = z + o.depth_noise * z * z * noise + offset;
      const long units = std::lround(measured * 1e4);  // 0.1 mm
      if (units > 0 && units <= 65535) out[i] = static_cast<uint16_t>(units);
    }
  }
  return out;
}

StatusOr<SynthFrame> SceneMaker::MakeFrame(int index) {
  const SceneOptions& o = options_;
  const uint64_t seed = seed_;
  std::vector<Model>& models = models_;
  const Intrinsics& K = o.camera;
  const int w = K.width, h = K.height;
  Rng rng(seed, kSceneStream, static_cast<uint64_t>(index));

  // ---- The camera over the table: z up, the table top z = 0 -----------------------------------
  const double reach = rng.Uniform(0.7, 1.1), elevation = rng.Uniform(30, 60) * kDeg, yaw = rng.Uniform(0, 360) * kDeg;
  const Eigen::Vector3d target(rng.Uniform(-0.05, 0.05), rng.Uniform(-0.05, 0.05), 0);
  const Eigen::Vector3d eye =
      target + reach * Eigen::Vector3d(-std::cos(elevation) * std::cos(yaw), -std::cos(elevation) * std::sin(yaw),
                                       std::sin(elevation));
  const Eigen::Vector3d forward = (target - eye).normalized();
  const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d down = forward.cross(right);
  Eigen::Matrix3d R_cam_world;
  R_cam_world.row(0) = right.transpose(), R_cam_world.row(1) = down.transpose(), R_cam_world.row(2) = forward.transpose();
  const SE3 T_cam_world(R_cam_world, -R_cam_world * eye);
  const SE3 T_world_cam = T_cam_world.Inverse();
  // The table: a rectangle about the target, the floor 0.75 m below it.
  const double table_x = rng.Uniform(0.5, 0.9), table_y = rng.Uniform(0.4, 0.7);
  const bool wood = rng.Uniform() < 0.5;
  Eigen::Vector3d table_albedo(rng.Uniform(0.25, 0.8), rng.Uniform(0.2, 0.7), rng.Uniform(0.15, 0.6));
  if (!wood) table_albedo = Eigen::Vector3d::Constant(rng.Uniform(0.3, 0.85));

  // ---- The objects: drawn, rested, turned, placed ---------------------------------------------
  std::vector<size_t> order(models.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  for (size_t i = order.size(); i > 1; --i) std::swap(order[i - 1], order[rng.NextU64() % i]);
  const int wanted = o.min_objects + static_cast<int>(rng.NextU64() % static_cast<uint64_t>(o.max_objects - o.min_objects + 1));
  std::vector<Placed> placed;
  std::vector<std::pair<Eigen::Vector2d, double>> footprints;  // centre on the table, radius
  // A turned rest pose of model m and the radius of its footprint about its centre of mass.
  const auto draw_turn = [&](const Model& m, double* radius) {
    size_t rest = 0;
    if (m.rests.size() > 1 && rng.Uniform() < o.side_share) rest = 1 + rng.NextU64() % (m.rests.size() - 1);
    const Eigen::Matrix3d R_table_obj =
        Eigen::AngleAxisd(rng.Uniform(0, 2 * std::numbers::pi), Eigen::Vector3d::UnitZ()).toRotationMatrix() *
        m.rests[rest].R;
    *radius = 0;
    for (const auto& v : m.mesh->vertices_m) {
      const Eigen::Vector3d p = R_table_obj * (v.cast<double>() - m.com);
      *radius = std::max(*radius, p.head<2>().norm());
    }
    return std::pair{rest, R_table_obj};
  };
  // Whether a footprint centred at `foot` (on the table plane) lies on the table, within the
  // distance range and clear of the footprints placed.
  const auto fits = [&](const Model& m, size_t rest, const Eigen::Vector3d& foot, double radius) {
    if (std::fabs(foot.x() - target.x()) > table_x - radius || std::fabs(foot.y() - target.y()) > table_y - radius)
      return false;
    const Eigen::Vector3d centre(foot.x(), foot.y(), m.rests[rest].height);
    const double distance = (centre - eye).norm();
    if (distance < o.min_distance_m || distance > o.max_distance_m) return false;
    for (const auto& [c, r] : footprints)
      if ((c - centre.head<2>()).norm() < 0.85 * (r + radius)) return false;
    return true;
  };
  const auto place = [&](size_t model, size_t rest, const Eigen::Matrix3d& R_table_obj, const Eigen::Vector3d& foot,
                         double radius) {
    const Model& m = models[model];
    const Eigen::Vector3d centre(foot.x(), foot.y(), m.rests[rest].height);
    footprints.emplace_back(centre.head<2>(), radius);
    const SE3 T_world_obj(R_table_obj, centre - R_table_obj * m.com);
    const Rgba8 plain{static_cast<uint8_t>(rng.Uniform(40, 230)), static_cast<uint8_t>(rng.Uniform(40, 230)),
                      static_cast<uint8_t>(rng.Uniform(40, 230)), 255};
    placed.push_back(Placed{model, T_cam_world * T_world_obj, plain});
  };
  for (size_t k = 0; k < order.size() && static_cast<int>(placed.size()) < wanted; ++k) {
    const Model& m = models[order[k]];
    double radius = 0;
    const auto [rest, R_table_obj] = draw_turn(m, &radius);
    for (int attempt = 0; attempt < (k == 0 && o.copies > 1 ? 400 : 40); ++attempt) {
      // A point of the table the camera sees, away from the image's borders.
      const double u = rng.Uniform(0.12, 0.88) * w, v = rng.Uniform(0.2, 0.88) * h;
      const Eigen::Vector3d ray = T_world_cam.R * Eigen::Vector3d((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1);
      if (ray.z() >= -1e-6) continue;
      const Eigen::Vector3d foot = eye - eye.z() / ray.z() * ray;
      if (!fits(m, rest, foot, radius)) continue;
      place(order[k], rest, R_table_obj, foot, radius);
      // The first object's copies: each beside the one before it, their footprints' circles
      // touching or up to 10 % of their radii apart (objects as round as cans touch). Where one
      // does not fit, the group starts again elsewhere.
      bool all_fit = true;
      for (int copy = 1; k == 0 && copy < o.copies && all_fit; ++copy) {
        double copy_radius = 0;
        const auto [copy_rest, R_copy] = draw_turn(m, &copy_radius);
        const auto [last_centre, last_radius] = footprints.back();
        all_fit = false;
        for (int copy_attempt = 0; copy_attempt < 40 && !all_fit; ++copy_attempt) {
          const double angle = rng.Uniform(0, 2 * std::numbers::pi);
          const double gap = (last_radius + copy_radius) * rng.Uniform(1.0, 1.1);
          const Eigen::Vector3d copy_foot(last_centre.x() + gap * std::cos(angle),
                                          last_centre.y() + gap * std::sin(angle), 0);
          const Eigen::Vector3d seen = T_cam_world * Eigen::Vector3d(copy_foot.x(), copy_foot.y(), 0);
          if (seen.z() <= 0) continue;
          const double u = K.fx * seen.x() / seen.z() + K.cx, v = K.fy * seen.y() / seen.z() + K.cy;
          if (u < 0.05 * w || u > 0.95 * w || v < 0.1 * h || v > 0.95 * h) continue;  // in view
          if (!fits(m, copy_rest, copy_foot, copy_radius)) continue;
          place(order[k], copy_rest, R_copy, copy_foot, copy_radius);
          all_fit = true;
        }
      }
      if (all_fit) break;
      placed.clear(), footprints.clear();
    }
  }
  if (placed.empty()) return Internal("no object could be placed in frame " + std::to_string(index));

  // ---- Light ----------------------------------------------------------------------------------
  const double light_elevation = rng.Uniform(25, 85) * kDeg, light_azimuth = rng.Uniform(0, 360) * kDeg;
  const Eigen::Vector3d to_light_cam =
      T_cam_world.R * Eigen::Vector3d(std::cos(light_elevation) * std::cos(light_azimuth),
                                      std::cos(light_elevation) * std::sin(light_azimuth), std::sin(light_elevation));
  const Eigen::Vector3d light = LightColour(rng.Uniform(3000, 7500)) * rng.Uniform(0.7, 1.3);
  const double ambient = rng.Uniform(0.15, 0.45);

  // ---- Render: each object's z-buffer over the whole image, then the nearest surface wins -----
  render::RasterParams params;
  params.fx = static_cast<float>(K.fx), params.fy = static_cast<float>(K.fy);
  params.cx = static_cast<float>(K.cx), params.cy = static_cast<float>(K.cy);
  params.box = render::PixelRect{0, 0, w, h};
  const size_t pixels = static_cast<size_t>(w) * h;
  std::vector<std::vector<float>> zbuf;
  // Objects hidden below min_visible are taken out and the rest rendered again.
  std::vector<float> depth;
  std::vector<int> owner;  // index into placed; -1 table, -2 floor, -3 nothing
  for (;;) {
    zbuf.assign(placed.size(), std::vector<float>(pixels, INFINITY));
    for (size_t i = 0; i < placed.size(); ++i) {
      const Mesh& mesh = *models[placed[i].model].mesh;
      std::vector<render::ScreenVertex> sv(mesh.vertices_m.size());
      render::ProjectVertices(mesh.vertices_m, placed[i].T_cam_obj.R.cast<float>(), placed[i].T_cam_obj.t.cast<float>(),
                              params, sv);
      RasterCounters stats;
      render::RasterizeDepthReference(sv, mesh.triangles, params, zbuf[i].data(), &stats);
    }
    depth.assign(pixels, INFINITY);
    owner.assign(pixels, -3);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t p = static_cast<size_t>(y) * w + x;
        const Eigen::Vector3d ray = T_world_cam.R * Eigen::Vector3d((x - K.cx) / K.fx, (y - K.cy) / K.fy, 1);
        if (ray.z() < -1e-9) {  // the table, or the floor beyond it
          const Eigen::Vector3d hit = eye - eye.z() / ray.z() * ray;
          if (std::fabs(hit.x() - target.x()) <= table_x && std::fabs(hit.y() - target.y()) <= table_y) {
            depth[p] = static_cast<float>(-eye.z() / ray.z()), owner[p] = -1;
          } else {
            depth[p] = static_cast<float>(-(eye.z() + 0.75) / ray.z()), owner[p] = -2;
          }
        }
        for (size_t i = 0; i < placed.size(); ++i)
          if (zbuf[i][p] < depth[p]) depth[p] = zbuf[i][p], owner[p] = static_cast<int>(i);
      }
    std::vector<int> all(placed.size(), 0), visible(placed.size(), 0);
    for (size_t p = 0; p < pixels; ++p) {
      for (size_t i = 0; i < placed.size(); ++i) all[i] += std::isfinite(zbuf[i][p]);
      if (owner[p] >= 0) ++visible[static_cast<size_t>(owner[p])];
    }
    std::vector<Placed> kept;
    for (size_t i = 0; i < placed.size(); ++i)
      if (all[i] > 0 && visible[i] >= o.min_visible * all[i] && visible[i] > 0) kept.push_back(placed[i]);
    if (kept.size() == placed.size()) break;
    if (kept.empty()) return Internal("every object of frame " + std::to_string(index) + " is hidden");
    placed = std::move(kept);
  }

  // ---- Shade: the surface each pixel shows, its albedo and normal ---------------------------
  for (const Placed& pl : placed) {
    Model& m = models[pl.model];
    if (!m.grid) m.grid = std::make_unique<render::TriangleGrid>(*m.mesh);
  }
  std::vector<Eigen::Vector3f> normals(pixels, Eigen::Vector3f::Zero());
  SynthFrame frame;
  frame.K = K;
  frame.T_cam_world = T_cam_world;
  frame.colour.width = w, frame.colour.height = h;
  frame.colour.rgba.assign(4 * pixels, 255);
  const Eigen::Vector3d table_normal = T_cam_world.R * Eigen::Vector3d::UnitZ();
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const size_t p = static_cast<size_t>(y) * w + x;
      uint8_t* rgba = &frame.colour.rgba[4 * p];
      if (owner[p] == -3) {
        rgba[0] = rgba[1] = rgba[2] = 20;
        continue;
      }
      const Eigen::Vector3d cam((x - K.cx) / K.fx * depth[p], (y - K.cy) / K.fy * depth[p], depth[p]);
      Eigen::Vector3d albedo, normal;
      if (owner[p] < 0) {
        normal = table_normal;
        const Eigen::Vector3d world = T_world_cam * cam;
        if (owner[p] == -2) {
          albedo = Eigen::Vector3d::Constant(0.12);
        } else if (wood) {  // grain along x
          const double grain = 0.5 + 0.5 * std::sin(60 * world.y() + 3 * std::sin(9 * world.x()));
          albedo = table_albedo * (0.75 + 0.25 * grain);
        } else {
          albedo = table_albedo;
        }
      } else {
        const Placed& pl = placed[static_cast<size_t>(owner[p])];
        const Model& m = models[pl.model];
        const Eigen::Vector3f q = (pl.T_cam_obj.Inverse() * cam).cast<float>();
        const auto nearest = m.grid->NearestTriangle(q);
        const auto& tri = m.mesh->triangles[nearest.triangle];
        const Eigen::Vector3f a = m.mesh->vertices_m[tri[0]], b = m.mesh->vertices_m[tri[1]],
                              c = m.mesh->vertices_m[tri[2]];
        normal = pl.T_cam_obj.R * (b - a).cross(c - a).normalized().cast<double>();
        Rgba8 s = appearance::SurfaceColour(*m.mesh, nearest.triangle, Barycentric(q, a, b, c));
        if (s.a < 128) s = pl.plain;
        albedo = Eigen::Vector3d(SrgbToLinear(s.r), SrgbToLinear(s.g), SrgbToLinear(s.b));
      }
      normals[p] = normal.cast<float>();
      const double lambert = std::max(0.0, normal.dot(to_light_cam));
      const Eigen::Vector3d lit = albedo.cwiseProduct(light) * (ambient + (1 - ambient) * lambert);
      for (int ch = 0; ch < 3; ++ch) rgba[ch] = LinearToSrgb(lit[ch]);
    }
  }
  // ---- The sensors ----------------------------------------------------------------------------
  const uint64_t frame_seed = HashCombine(seed, static_cast<uint64_t>(index));
  PhotometricTransform noise;
  noise.kind = PhotometricTransform::Kind::kNoise;
  noise.sigma = o.colour_noise;
  MCPOSE_ASSIGN_OR_RETURN(frame.colour, ApplyPhotometric(noise, frame.colour, HashCombine(frame_seed, kColourStream)));
  if (o.jpeg_quality > 0) {
    PhotometricTransform jpeg;
    jpeg.kind = PhotometricTransform::Kind::kJpeg;
    jpeg.quality = o.jpeg_quality;
    MCPOSE_ASSIGN_OR_RETURN(frame.colour, ApplyPhotometric(jpeg, frame.colour, 0));
  }
  frame.depth = MeasureDepth(depth, normals, K, o, frame_seed);

  // ---- Ground truth -----------------------------------------------------------------------------
  for (size_t i = 0; i < placed.size(); ++i) {
    SynthInstance inst;
    inst.obj_id = models[placed[i].model].obj_id;
    inst.T_cam_obj = placed[i].T_cam_obj;
    inst.visible.width = w, inst.visible.height = h;
    inst.visible.values.assign(pixels, 0);
    int box_all[4] = {w, h, -1, -1}, box_vis[4] = {w, h, -1, -1};
    const auto grow = [](int* b, int x, int y) {
      b[0] = std::min(b[0], x), b[1] = std::min(b[1], y), b[2] = std::max(b[2], x), b[3] = std::max(b[3], y);
    };
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t p = static_cast<size_t>(y) * w + x;
        if (std::isfinite(zbuf[i][p])) ++inst.px_count_all, grow(box_all, x, y);
        if (owner[p] == static_cast<int>(i)) {
          inst.visible.values[p] = 255;
          ++inst.px_count_visib;
          inst.px_count_valid += frame.depth[p] > 0;
          grow(box_vis, x, y);
        }
      }
    const auto box = [](const int* b, int* out) {
      if (b[2] < 0) {
        out[0] = out[1] = out[2] = out[3] = -1;
        return;
      }
      out[0] = b[0], out[1] = b[1], out[2] = b[2] - b[0] + 1, out[3] = b[3] - b[1] + 1;
    };
    box(box_all, inst.bbox_obj);
    box(box_vis, inst.bbox_visib);
    frame.instances.push_back(std::move(inst));
  }
  return frame;
}

}  // namespace mcpose::synth

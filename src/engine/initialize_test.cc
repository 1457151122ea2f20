#include "engine/initialize.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "engine/box_scorer.h"
#include "core/rest_pose.h"
#include "engine/context.h"
#include "synthetic_mesh.h"

namespace mcpose::engine {
namespace {

// A 320 x 240 frame whose box [100, 60, 120, 100] sees a thin near surface at 0.6 m on its
// left fifth and a background at 0.9 m elsewhere; a slab 12 x 4 x 2 cm whose origin is not its
// centre.
struct Scene {
  Intrinsics K{600, 600, 160, 120, 320, 240};
  DepthImage depth;
  Mesh mesh;
  Detection box{1, 1, 5, 0.9, 100, 60, 120, 100};
};

Scene MakeScene(float near_m = 0.6f, float far_m = 0.9f) {
  Scene s;
  s.depth.width = 320, s.depth.height = 240;
  s.depth.depth_m.assign(320 * 240, far_m);
  for (int y = 60; y < 160; ++y)
    for (int x = 100; x < 124; ++x) s.depth.depth_m[static_cast<size_t>(y) * 320 + x] = near_m;
  testing::AddBox(&s.mesh, Eigen::Vector3f(0.01f, -0.02f, 0.03f), Eigen::Vector3f(0.13f, 0.02f, 0.05f));
  return s;
}

filter::ParticleSet Initialize(const Scene& s, const EstimatorOptions& o) {
  Context context(o);
  const std::vector<Detection> boxes = {s.box};
  auto scorer = BoxScorer::Create(context, s.K, s.depth, s.mesh, boxes);
  EXPECT_TRUE(scorer.ok()) << scorer.status().ToString();
  filter::ParticleSet p;  // empty when the scorer failed: every test then fails on its size
  if (scorer.ok()) InitializeSamples(**scorer, o, 7, &p);
  return p;
}

EstimatorOptions NoJitter() {
  EstimatorOptions o;
  o.samples = 200;
  o.init.sigma_t_m = 0;
  o.init.rest_share = 0;   // the tests of rest samples set it
  o.init.rest_spread = 0;  // and this
  return o;
}

// The ray through the box centre, z = 1.
Eigen::Vector3d BoxRay(const Scene& s) {
  return {(s.box.x + 0.5 * s.box.w - s.K.cx) / s.K.fx, (s.box.y + 0.5 * s.box.h - s.K.cy) / s.K.fy, 1.0};
}

TEST(InitializeSamples, FrontSamplesHaveTheirTurnedModelsNearestPointAtTheQuantile) {
  const Scene s = MakeScene();
  EstimatorOptions o = NoJitter();
  o.init.front_share = 1;
  o.init.front_quantile = 0.1;  // within the near fifth of the box
  const filter::ParticleSet p = Initialize(s, o);
  const Eigen::Vector3d ray = BoxRay(s);
  const Eigen::Vector3d centre = 0.5 * (s.mesh.BoundsMin() + s.mesh.BoundsMax()).cast<double>();
  double min_depth = INFINITY, max_depth = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    double nearest = INFINITY;
    for (const Eigen::Vector3f& v : s.mesh.vertices_m)
      nearest = std::min(nearest, (p.R_cam_obj[i] * v.cast<double>() + p.t_cam_obj_m[i]).z());
    EXPECT_NEAR(nearest, 0.6, 1e-6) << "sample " << i;
    // The model's bounding-box centre lies on the box's ray.
    const Eigen::Vector3d c = p.R_cam_obj[i] * centre + p.t_cam_obj_m[i];
    EXPECT_NEAR((c / c.z() - ray).norm(), 0.0, 1e-9) << "sample " << i;
    min_depth = std::min(min_depth, c.z()), max_depth = std::max(max_depth, c.z());
  }
  // Each turn sits at its own depth: end on (6 cm behind the front) or face on (1 cm).
  EXPECT_LT(min_depth, 0.6 + 0.015);
  EXPECT_GT(max_depth, 0.6 + 0.05);
}

TEST(InitializeSamples, CentreSamplesStartAtOneDepthBehindTheQuantileWhateverTheTurn) {
  const Scene s = MakeScene();
  EstimatorOptions o = NoJitter();
  o.init.front_share = 0;
  o.init.depth_quantile = 0.5;  // the background
  const filter::ParticleSet p = Initialize(s, o);
  // The origin at the median depth (0.9 m) plus half the median side (4 cm).
  const Eigen::Vector3d expected = BoxRay(s) * (0.9 + 0.02);
  for (size_t i = 0; i < p.size(); ++i) EXPECT_NEAR((p.t_cam_obj_m[i] - expected).norm(), 0.0, 1e-6) << i;
}

TEST(InitializeSamples, WithoutValidDepthEverySampleStartsWhereTheObjectFillsTheBox) {
  Scene s = MakeScene();
  std::fill(s.depth.depth_m.begin(), s.depth.depth_m.end(), 0.f);
  EstimatorOptions o = NoJitter();
  o.init.front_share = 1;
  const filter::ParticleSet front = Initialize(s, o);
  o.init.front_share = 0;
  const filter::ParticleSet centre = Initialize(s, o);
  ASSERT_EQ(front.size(), centre.size());
  for (size_t i = 0; i < front.size(); ++i) {
    EXPECT_EQ(front.t_cam_obj_m[i], centre.t_cam_obj_m[i]);
    EXPECT_EQ(front.R_cam_obj[i], centre.R_cam_obj[i]);
  }
  EXPECT_GT(front.t_cam_obj_m[0].z(), 0.1);
}

TEST(InitializeSamples, FrontShareSplitsEachBoxsSamplesWithoutChangingTheirDraws) {
  const Scene s = MakeScene();
  EstimatorOptions o = NoJitter();
  o.init.sigma_t_m = 0.01;  // the jitter's draws must not move either
  o.init.front_share = 1;
  const filter::ParticleSet front = Initialize(s, o);
  o.init.front_share = 0;
  const filter::ParticleSet centre = Initialize(s, o);
  o.init.front_share = 0.5;  // the default
  ASSERT_EQ(o.init.front_share, EstimatorOptions{}.init.front_share);
  const filter::ParticleSet half = Initialize(s, o);
  for (size_t i = 0; i < half.size(); ++i) {
    EXPECT_EQ(half.R_cam_obj[i], centre.R_cam_obj[i]);
    EXPECT_EQ(half.t_cam_obj_m[i], (i % 2 == 1 ? front : centre).t_cam_obj_m[i]) << i;
  }
  o.init.front_share = 0.25;
  const filter::ParticleSet quarter = Initialize(s, o);
  int at_front = 0;
  for (size_t i = 0; i < quarter.size(); ++i) at_front += quarter.t_cam_obj_m[i] == front.t_cam_obj_m[i];
  EXPECT_EQ(at_front, 50);
}

// A table tilted towards the camera (normal n, n . x + offset = 0) over the whole 320 x 240
// frame, and inside the box an object about 5 cm above it.
Scene MakeTableScene(const Eigen::Vector3d& n, double offset) {
  Scene s = MakeScene();
  for (int y = 0; y < 240; ++y)
    for (int x = 0; x < 320; ++x) {
      const Eigen::Vector3d ray((x - s.K.cx) / s.K.fx, (y - s.K.cy) / s.K.fy, 1.0);
      double z = -offset / n.dot(ray);
      if (x >= 100 && x < 220 && y >= 60 && y < 160) z *= 0.92;  // 0.08 offset nearer: 4.8 cm above
      s.depth.depth_m[static_cast<size_t>(y) * 320 + x] = static_cast<float>(z);
    }
  return s;
}

TEST(SupportPlane, TheTableAroundTheBoxIsFound) {
  const Eigen::Vector3d n = Eigen::Vector3d(0, -0.8, -0.6).normalized();  // towards the camera
  const Scene s = MakeTableScene(n, 0.6);
  const std::optional<SupportPlane> plane = FindSupportPlane(s.depth, s.K, s.box, 0, 7, 0);
  ASSERT_TRUE(plane.has_value());
  EXPECT_GT(plane->normal.dot(n), 0.999);
  EXPECT_NEAR(plane->offset, 0.6, 0.005);
  EXPECT_GT(plane->share, 0.95);
  // The same seed and stream, the same plane; a wall behind the box is no support.
  const std::optional<SupportPlane> again = FindSupportPlane(s.depth, s.K, s.box, 0, 7, 0);
  EXPECT_EQ(again->normal, plane->normal);
  Scene behind = MakeScene(1.2f, 0.9f);  // the box's surface behind the plane around it
  for (int y = 60; y < 160; ++y)
    for (int x = 100; x < 220; ++x) behind.depth.depth_m[static_cast<size_t>(y) * 320 + x] = 1.2f;
  EXPECT_FALSE(FindSupportPlane(behind.depth, behind.K, behind.box, 0, 7, 0).has_value());
}

// With rest_share 1 every sample lies on a stable face of the slab on the table: its lowest
// vertex on the plane, its centre of mass on the ray through the box centre.
TEST(InitializeSamples, RestSamplesLieOnTheSupportPlane) {
  const Eigen::Vector3d n = Eigen::Vector3d(0, -0.8, -0.6).normalized();
  const Scene s = MakeTableScene(n, 0.6);
  EstimatorOptions o = NoJitter();
  o.init.rest_share = 1;
  const filter::ParticleSet p = Initialize(s, o);
  ASSERT_EQ(p.size(), 200u);
  const Eigen::Vector3d com = CentreOfMass(s.mesh);
  std::set<long> heights;
  for (size_t i = 0; i < p.size(); ++i) {
    double lowest = INFINITY;
    for (const auto& v : s.mesh.vertices_m) lowest = std::min(lowest, n.dot(p.R_cam_obj[i] * v.cast<double>() + p.t_cam_obj_m[i]) + 0.6);
    EXPECT_NEAR(lowest, 0.0, 2e-3) << "sample " << i;
    const Eigen::Vector3d c = p.R_cam_obj[i] * com + p.t_cam_obj_m[i];
    EXPECT_LT((c / c.z() - BoxRay(s)).norm(), 1e-9);
    heights.insert(std::lround(1000 * (n.dot(c) + 0.6)));  // the centre of mass's height, mm
  }
  EXPECT_GE(heights.size(), 2u);  // more than one face down
  EXPECT_LE(*heights.rbegin(), 61);  // none higher than the slab's half length
}

// With rest_spread 0.5 the rest samples stand on rays through the box's central half: the
// centre of mass of each projects there, and they spread over it, each still on the plane.
TEST(InitializeSamples, RestSamplesSpreadOverTheBoxsCentralShare) {
  const Eigen::Vector3d n = Eigen::Vector3d(0, -0.8, -0.6).normalized();
  const Scene s = MakeTableScene(n, 0.6);
  EstimatorOptions o = NoJitter();
  o.init.rest_share = 1;
  o.init.rest_spread = 0.5;
  ASSERT_EQ(o.init.rest_spread, EstimatorOptions{}.init.rest_spread);
  const filter::ParticleSet p = Initialize(s, o);
  ASSERT_EQ(p.size(), 200u);
  const Eigen::Vector3d com = CentreOfMass(s.mesh);
  const double uc = s.box.x + 0.5 * s.box.w, vc = s.box.y + 0.5 * s.box.h;
  double widest_u = 0, widest_v = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    double lowest = INFINITY;
    for (const auto& v : s.mesh.vertices_m) lowest = std::min(lowest, n.dot(p.R_cam_obj[i] * v.cast<double>() + p.t_cam_obj_m[i]) + 0.6);
    EXPECT_NEAR(lowest, 0.0, 2e-3) << "sample " << i;
    const Eigen::Vector3d c = p.R_cam_obj[i] * com + p.t_cam_obj_m[i];
    const double du = s.K.fx * c.x() / c.z() + s.K.cx - uc, dv = s.K.fy * c.y() / c.z() + s.K.cy - vc;
    EXPECT_LE(std::fabs(du), 0.25 * s.box.w + 1e-9) << "sample " << i;
    EXPECT_LE(std::fabs(dv), 0.25 * s.box.h + 1e-9) << "sample " << i;
    widest_u = std::max(widest_u, std::fabs(du)), widest_v = std::max(widest_v, std::fabs(dv));
  }
  EXPECT_GT(widest_u, 0.2 * s.box.w);
  EXPECT_GT(widest_v, 0.2 * s.box.h);
}

TEST(InitializeSamples, AGivenCountOfSamplesIsSpreadOverTheBoxesAsTheSamplesAre) {
  const Scene s = MakeScene();
  const EstimatorOptions o = NoJitter();
  Context context(o);
  const std::vector<Detection> boxes = {s.box, Detection{1, 1, 5, 0.3, 20, 20, 40, 40}};
  auto scorer = BoxScorer::Create(context, s.K, s.depth, s.mesh, boxes);
  ASSERT_TRUE(scorer.ok()) << scorer.status().ToString();
  filter::ParticleSet wide;
  InitializeSamples(**scorer, o, 7, &wide, 8 * o.samples);
  ASSERT_EQ(wide.size(), 1600u);
  const long first_box = std::count(wide.box.begin(), wide.box.end(), 0);
  EXPECT_EQ(first_box, 1200);  // scores 0.9 and 0.3: three quarters
}

TEST(InitializeSamples, RestSamplesComeFromTheCentreSamplesFirst) {
  const Scene s = MakeTableScene(Eigen::Vector3d(0, -0.8, -0.6).normalized(), 0.6);
  EstimatorOptions o = NoJitter();
  o.init.front_share = 0.5;
  const filter::ParticleSet none = Initialize(s, o);
  const auto same = [](const filter::ParticleSet& a, const filter::ParticleSet& b, size_t i) {
    return a.R_cam_obj[i] == b.R_cam_obj[i] && a.t_cam_obj_m[i] == b.t_cam_obj_m[i];
  };
  // Half at rest (the default): every centre sample (even index) at rest, every front one kept.
  o.init.rest_share = 0.5;
  ASSERT_EQ(o.init.rest_share, EstimatorOptions{}.init.rest_share);
  const filter::ParticleSet half = Initialize(s, o);
  for (size_t i = 0; i < half.size(); ++i) EXPECT_EQ(same(half, none, i), i % 2 == 1) << i;
  // A quarter: every other centre sample.
  o.init.rest_share = 0.25;
  const filter::ParticleSet quarter = Initialize(s, o);
  for (size_t i = 0; i < quarter.size(); ++i) EXPECT_EQ(same(quarter, none, i), i % 4 != 2) << i;
  // Three quarters: every centre sample and every other front one.
  o.init.rest_share = 0.75;
  const filter::ParticleSet most = Initialize(s, o);
  int kept = 0;
  for (size_t i = 0; i < most.size(); ++i) kept += same(most, none, i);
  EXPECT_EQ(kept, 50);
  for (size_t i = 0; i < most.size(); i += 2) EXPECT_FALSE(same(most, none, i)) << i;
}

}  // namespace
}  // namespace mcpose::engine

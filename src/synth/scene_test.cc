#include "mcpose/synth_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/rest_pose.h"
#include "synthetic_mesh.h"

namespace mcpose::synth {
namespace {

// A closed cylinder (a can) of radius r and height h about z, centred on the origin.
Mesh Can(double r, double h, int sides = 48) {
  Mesh m;
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i < sides; ++i) {
      const double a = 2 * std::numbers::pi * i / sides;
      m.vertices_m.emplace_back(r * std::cos(a), r * std::sin(a), (k - 0.5) * h);
    }
  m.vertices_m.emplace_back(0, 0, -0.5 * h);
  m.vertices_m.emplace_back(0, 0, 0.5 * h);
  const uint32_t bottom = 2 * sides, top = bottom + 1;
  for (int i = 0; i < sides; ++i) {
    const uint32_t a = i, b = (i + 1) % sides, c = sides + i, d = sides + (i + 1) % sides;
    m.triangles.push_back({a, b, d}), m.triangles.push_back({a, d, c});
    m.triangles.push_back({bottom, b, a}), m.triangles.push_back({top, c, d});
  }
  return m;
}

TEST(RestPose, ABoxLiesOnItsLargestFaceFirst) {
  Mesh box;
  testing::AddBox(&box, {-0.10f, -0.04f, -0.02f}, {0.10f, 0.04f, 0.02f});
  EXPECT_LT(CentreOfMass(box).norm(), 1e-6);
  auto rests = StableRestPoses(box);
  ASSERT_TRUE(rests.ok()) << rests.status().ToString();
  ASSERT_EQ(rests->size(), 6u);  // every face of a box is stable
  // Lowest first: on a 20 x 8 face (height 2 cm), then on a 20 x 4 face (4 cm), then the ends (10 cm).
  EXPECT_NEAR((*rests)[0].height, 0.02, 1e-6);
  EXPECT_NEAR((*rests)[0].face_area, 0.2 * 0.08, 1e-6);
  EXPECT_NEAR((*rests)[2].height, 0.04, 1e-6);
  EXPECT_NEAR((*rests)[5].height, 0.10, 1e-6);
  // Resting: the face's normal points down, so the model's z axis (the thin one) is vertical.
  const Eigen::Vector3d z = (*rests)[0].R * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(std::fabs(z.z()), 1.0, 1e-6);
  // Every vertex lies on or above the plane.
  for (const RestPose& r : *rests) {
    double lowest = INFINITY;
    for (const auto& v : box.vertices_m) lowest = std::min(lowest, (r.R * v.cast<double>()).z() + r.height);
    EXPECT_NEAR(lowest, 0, 1e-6);
  }
}

TEST(RestPose, ACanStandsOrLies) {
  // A tall can: lying on its side is lowest (its radius, less the chord of the hull's facets
  // merged within a millimetre), standing on an end highest (half its height); both are stable.
  auto tall = StableRestPoses(Can(0.03, 0.12));
  ASSERT_TRUE(tall.ok());
  ASSERT_GE(tall->size(), 4u);
  EXPECT_NEAR((*tall)[0].height, 0.029, 0.0015);
  EXPECT_NEAR(std::fabs(((*tall)[0].R * Eigen::Vector3d::UnitZ()).z()), 0.0, 0.03);  // its axis about level
  EXPECT_NEAR(tall->back().height, 0.06, 1e-6);
  EXPECT_NEAR(std::fabs((tall->back().R * Eigen::Vector3d::UnitZ()).z()), 1.0, 1e-6);  // upright
  // A flat can (a tuna can) stands on an end first.
  auto flat = StableRestPoses(Can(0.045, 0.03));
  ASSERT_TRUE(flat.ok());
  ASSERT_GE(flat->size(), 2u);
  EXPECT_NEAR((*flat)[0].height, 0.015, 1e-6);
  EXPECT_NEAR((*flat)[1].height, 0.015, 1e-6);
  EXPECT_GT((*flat)[2].height, 0.04);
  // Fewer than four points, or all in a plane: no hull.
  Mesh tri;
  tri.vertices_m = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  tri.triangles = {{0, 1, 2}};
  EXPECT_FALSE(StableRestPoses(tri).ok());
}

TEST(DepthSensor, NoiseGrowsWithDepthAndEdgesAndGrazingLoseMeasurements) {
  SceneOptions o;
  o.camera = Intrinsics{500, 500, 100, 100, 200, 200};
  o.depth_offset_m = 0;
  const int w = 200, h = 200;
  // Left half a wall at 0.6 m, right half at 1.2 m, facing the camera.
  std::vector<float> z(w * h);
  std::vector<Eigen::Vector3f> n(w * h, Eigen::Vector3f(0, 0, -1));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) z[y * w + x] = x < 100 ? 0.6f : 1.2f;
  const std::vector<uint16_t> d = MeasureDepth(z, n, o.camera, o, 7);
  auto spread = [&](int x0, int x1, double truth) {
    double s2 = 0;
    int count = 0;
    for (int y = 10; y < 190; ++y)
      for (int x = x0; x < x1; ++x) {
        const uint16_t v = d[y * w + x];
        if (v == 0) continue;
        s2 += std::pow(v * 1e-4 - truth, 2), ++count;
      }
    return std::sqrt(s2 / count);
  };
  const double near = spread(10, 90, 0.6), far = spread(110, 190, 1.2);
  EXPECT_NEAR(near, o.depth_noise * 0.36, 0.2 * o.depth_noise * 0.36);
  EXPECT_NEAR(far, o.depth_noise * 1.44, 0.2 * o.depth_noise * 1.44);
  // The depth edge between the walls loses about edge_dropout of its pixels; the walls none.
  int edge_missing = 0, inside_missing = 0;
  for (int y = 0; y < h; ++y) {
    edge_missing += (d[y * w + 99] == 0) + (d[y * w + 100] == 0);
    inside_missing += d[y * w + 50] == 0;
  }
  EXPECT_NEAR(edge_missing / (2.0 * h), o.edge_dropout, 0.12);
  EXPECT_EQ(inside_missing, 0);
  // A wall seen at a grazing angle gives no depth; the same seed gives the same measurements.
  std::vector<Eigen::Vector3f> grazing(w * h, Eigen::Vector3f(0.99f, 0, -0.14f).normalized());
  const std::vector<uint16_t> g = MeasureDepth(z, grazing, o.camera, o, 7);
  EXPECT_EQ(g[50 * w + 50], 0);
  EXPECT_EQ(MeasureDepth(z, n, o.camera, o, 7), d);
  EXPECT_NE(MeasureDepth(z, n, o.camera, o, 8), d);
}

struct Models {
  Mesh box, can;
  std::vector<SceneObject> objects() const { return {{1, &box}, {2, &can}}; }
  Models() {
    box = testing::LatticeBox(Eigen::Vector3f(-0.06f, -0.04f, -0.025f), Eigen::Vector3f(0.06f, 0.04f, 0.025f), 4,
                              [](int f, const Eigen::Vector3f&) {
                                return Rgba8{static_cast<uint8_t>(40 * f + 20), 120, static_cast<uint8_t>(200 - 30 * f), 255};
                              });
    can = Can(0.035, 0.1);  // no colour: a plain one
  }
};

TEST(SceneMaker, FramesAreTheSameForASeedAndShowTheirObjects) {
  const Models m;
  SceneOptions o;
  o.min_objects = 1, o.max_objects = 2;
  auto a = SceneMaker::Create(m.objects(), o, 3);
  auto b = SceneMaker::Create(m.objects(), o, 3);
  ASSERT_TRUE(a.ok() && b.ok()) << a.status().ToString();
  // Frame 2 alone equals frame 2 made after frames 0 and 1.
  ASSERT_TRUE((*a)->MakeFrame(0).ok());
  ASSERT_TRUE((*a)->MakeFrame(1).ok());
  auto f = (*a)->MakeFrame(2), g = (*b)->MakeFrame(2);
  ASSERT_TRUE(f.ok() && g.ok()) << f.status().ToString();
  EXPECT_EQ(f->depth, g->depth);
  EXPECT_EQ(f->colour.rgba, g->colour.rgba);
  ASSERT_FALSE(f->instances.empty());
  for (const SynthInstance& s : f->instances) {
    EXPECT_GE(s.visib_fract(), o.min_visible);
    EXPECT_LE(s.px_count_visib, s.px_count_all);
    EXPECT_LE(s.px_count_valid, s.px_count_visib);
    const double distance = s.T_cam_obj.t.norm();
    EXPECT_GT(distance, o.min_distance_m - 0.1);
    EXPECT_LT(distance, o.max_distance_m + 0.1);
    // The object's visible pixels measure about its depth.
    int near = 0, valid = 0;
    for (size_t p = 0; p < s.visible.values.size(); ++p) {
      if (!s.visible.values[p] || f->depth[p] == 0) continue;
      ++valid;
      near += std::fabs(f->depth[p] * 1e-4 - s.T_cam_obj.t.z()) < 0.15;
    }
    EXPECT_EQ(valid, s.px_count_valid);
    EXPECT_GT(near, 0.9 * valid);
  }
  // Another seed, another frame.
  auto c = SceneMaker::Create(m.objects(), o, 4);
  ASSERT_TRUE(c.ok());
  EXPECT_NE((*c)->MakeFrame(2)->depth, f->depth);
}

// --copies: the first object of a frame appears that many times, each copy beside the one
// before it (the footprints' circles at most 10 % apart).
TEST(SceneMaker, CopiesOfOneObjectStandSideBySide) {
  const Models m;
  SceneOptions o;
  o.min_objects = o.max_objects = 3;
  o.copies = 3;
  o.min_visible = 0;
  auto maker = SceneMaker::Create(m.objects(), o, 11);
  ASSERT_TRUE(maker.ok()) << maker.status().ToString();
  for (int frame = 0; frame < 4; ++frame) {
    auto f = (*maker)->MakeFrame(frame);
    ASSERT_TRUE(f.ok()) << f.status().ToString();
    ASSERT_EQ(f->instances.size(), 3u) << "frame " << frame;
    const Mesh& mesh = f->instances[0].obj_id == 1 ? m.box : m.can;
    double radius = 0;  // the mesh's largest distance from its centre bounds each footprint's
    for (const auto& v : mesh.vertices_m) radius = std::max(radius, v.cast<double>().norm());
    for (size_t i = 0; i < 3; ++i) {
      EXPECT_EQ(f->instances[i].obj_id, f->instances[0].obj_id);
      if (i > 0) {
        const SE3& a = f->instances[i - 1].T_cam_obj;
        const SE3& b = f->instances[i].T_cam_obj;
        EXPECT_LT((a.t - b.t).norm(), 2.5 * radius + 0.01) << "frame " << frame << " copy " << i;
        EXPECT_GT((a.t - b.t).norm(), 0.01);
      }
    }
  }
  o.copies = 9;
  EXPECT_FALSE(SceneMaker::Create(m.objects(), o, 1).ok());
}

TEST(SceneMaker, RefusesBadOptions) {
  const Models m;
  SceneOptions o;
  o.min_objects = 5, o.max_objects = 2;
  auto r = SceneMaker::Create(m.objects(), o, 0);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("min_objects"), std::string::npos);
  EXPECT_FALSE(SceneMaker::Create({}, SceneOptions{}, 0).ok());
}

}  // namespace
}  // namespace mcpose::synth

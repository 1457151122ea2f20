#include "engine/twins.h"

#include <cmath>

#include <gtest/gtest.h>

#include "mcpose/estimator.h"
#include "synthetic_mesh.h"
#include "synthetic_scene.h"

namespace mcpose::engine {
namespace {

TEST(Twins, DistinctAxisIsACansAxis) {
  Mesh can_like, flat;
  testing::AddBox(&can_like, {-0.05f, -0.05f, -0.07f}, {0.05f, 0.05f, 0.07f});
  EXPECT_EQ(DistinctAxis(can_like), 2);
  testing::AddBox(&flat, {-0.05f, -0.01f, -0.05f}, {0.05f, 0.01f, 0.05f});
  EXPECT_EQ(DistinctAxis(flat), 1);
}

// The candidates keep the bounding-box centre where it is, start with the pose itself, and are
// the flips times the turns about the distinct axis.
TEST(Twins, CandidatesTurnAboutTheBoxCentre) {
  Mesh m;
  testing::AddBox(&m, {-0.02f, -0.03f, -0.08f}, {0.04f, 0.03f, 0.06f});
  const SE3 T(ExpSO3(Eigen::Vector3d(0.2, -0.4, 0.9)), Eigen::Vector3d(0.05, -0.02, 0.7));
  const std::vector<SE3> c = TwinCandidates(T, m, 90);
  ASSERT_EQ(c.size(), 8u);  // the turns, and the turns after a flip about x; no turn twice
  for (size_t i = 0; i < c.size(); ++i)
    for (size_t j = 0; j < i; ++j) EXPECT_GT(RotationAngle(c[i].R, c[j].R), 1e-6) << i << " " << j;
  EXPECT_TRUE(c[0].R.isApprox(T.R) && c[0].t.isApprox(T.t));
  const Eigen::Vector3d centre = (0.5f * (m.BoundsMin() + m.BoundsMax())).cast<double>();
  for (const SE3& s : c) {
    EXPECT_LT((s * centre - T * centre).norm(), 1e-12);
    EXPECT_NEAR(s.R.determinant(), 1.0, 1e-12);
  }
  // Candidate 4 is the flip about x (no turn): 180 degrees from T.
  EXPECT_NEAR(RotationAngle(c[4].R, T.R), M_PI, 1e-9);
}

// A box whose six faces have six colours, seen so that its three 180-degree turns show the
// camera the same depth: with colour the estimator finds the right one in every run; without,
// it cannot tell them apart and settles on a twin in some runs.
TEST(Twins, ColourTellsABoxFromItsDepthTwins) {
  const Eigen::Vector3f lo(-0.06f, -0.04f, -0.025f), hi(0.06f, 0.04f, 0.025f);
  const Rgba8 colours[6] = {{220, 40, 40, 255}, {40, 200, 40, 255}, {40, 40, 220, 255},
                            {220, 220, 40, 255}, {40, 200, 220, 255}, {200, 40, 200, 255}};
  auto colour_of = [&](const Eigen::Vector3f& p) {
    // The face whose plane the point lies on (closest), its colour.
    int best = 0;
    float d = INFINITY;
    for (int f = 0; f < 6; ++f) {
      const float e = std::fabs(p[f / 2] - (f % 2 ? hi[f / 2] : lo[f / 2]));
      if (e < d) d = e, best = f;
    }
    return colours[best];
  };
  const Mesh box = testing::LatticeBox(lo, hi, 8, [&](int f, const Eigen::Vector3f&) { return colours[f]; });
  ASSERT_TRUE(box.Validate("box").ok());
  const SE3 T_gt(ExpSO3(Eigen::Vector3d(0.5, -0.4, 0.3)), Eigen::Vector3d(0.0, 0.01, 0.6));
  const testing::SyntheticFrame frame = testing::RenderFrame(box, T_gt, colour_of, 5);
  int x0 = 320, y0 = 240, x1 = 0, y1 = 0;
  for (int y = 0; y < 240; ++y)
    for (int x = 0; x < 320; ++x)
      if (frame.visible.values[y * 320 + x]) x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
  const std::vector<Detection> boxes = {Detection{1, 1, 3, 0.9, double(x0), double(y0), double(x1 - x0 + 1), double(y1 - y0 + 1)}};
  // Runs: depth only; colour; colour with the twins within 0.05 of depth weight told apart by
  // colour alone.
  int right[3] = {0, 0, 0};
  for (int run = 0; run < 3; ++run) {
    const int with_colour = run > 0;
    EstimatorOptions o;
    o.samples = 300;
    o.max_iterations = 30;
    o.engine.threads = 2;
    o.appearance.enabled = with_colour;
    if (run == 2) o.appearance.twin_depth_margin = 0.05;
    auto est = Estimator::Create(o);
    ASSERT_TRUE(est.ok());
    for (uint64_t stream = 0; stream < 6; ++stream) {
      auto r = (*est)->Estimate(frame.K, frame.depth, &frame.colour, box, boxes, stream);
      ASSERT_TRUE(r.ok()) << r.status().ToString();
      EXPECT_EQ(r->colour, with_colour == 1);
      EXPECT_EQ(r->twins.ran, with_colour == 1);
      if (with_colour) {
        EXPECT_EQ(r->twins.candidates, 24);
      }
      right[run] += RotationAngle(r->T_cam_obj.R, T_gt.R) < 0.2;
    }
  }
  std::printf("  right turn found in %d of 6 runs without colour, %d of 6 with, %d of 6 by colour alone\n",
              right[0], right[1], right[2]);
  EXPECT_EQ(right[1], 6);
  EXPECT_EQ(right[2], 6);
  EXPECT_LE(right[0], 4);
}

}  // namespace
}  // namespace mcpose::engine

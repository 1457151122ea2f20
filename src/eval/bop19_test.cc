#include "mcpose/bop19.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

#include <gtest/gtest.h>

#include "synthetic_mesh.h"
#include "test_data.h"

namespace mcpose {
namespace {

constexpr double kStep = 2 * M_PI / 315;  // bop_toolkit's continuous step: ceil(pi / 0.01) turns

SE3 Pose(const Eigen::Matrix3d& R, const Eigen::Vector3d& t) { return SE3(R, t); }
Eigen::Matrix3d TurnZ(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix(); }

// Points on a circle of radius r about the z axis, at angles 2 pi k / n.
std::vector<Eigen::Vector3f> Circle(int n, double r) {
  std::vector<Eigen::Vector3f> pts;
  for (int k = 0; k < n; ++k)
    pts.emplace_back(static_cast<float>(r * std::cos(2 * M_PI * k / n)), static_cast<float>(r * std::sin(2 * M_PI * k / n)),
                     0.f);
  return pts;
}

TEST(Bop19Symmetries, IdentityDiscreteAndDiscretisedContinuous) {
  ModelInfo none;
  ASSERT_EQ(SymmetryTransformations(none).size(), 1u);
  EXPECT_TRUE(SymmetryTransformations(none)[0].R.isIdentity());

  ModelInfo can;
  can.continuous.push_back({Eigen::Vector3d::UnitZ(), Eigen::Vector3d(0.01, -0.02, 0.03)});
  const std::vector<SE3> turns = SymmetryTransformations(can);
  ASSERT_EQ(turns.size(), 315u);
  EXPECT_TRUE(turns[0].R.isApprox(Eigen::Matrix3d::Identity(), 1e-15));
  for (size_t i = 0; i < turns.size(); ++i) {
    // Each turn keeps the axis through the offset fixed and turns by i steps.
    const Eigen::Vector3d on_axis = can.continuous[0].offset_m + 0.5 * Eigen::Vector3d::UnitZ();
    EXPECT_NEAR((turns[i] * on_axis - on_axis).norm(), 0, 1e-15);
    EXPECT_NEAR(Eigen::AngleAxisd(turns[i].R).angle(), std::min(i * kStep, 2 * M_PI - i * kStep), 1e-9);
  }

  ModelInfo box = can;
  box.discrete.push_back(SE3(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix(), Eigen::Vector3d(0, 0, 0.1)));
  const std::vector<SE3> all = SymmetryTransformations(box);
  ASSERT_EQ(all.size(), 2u * 315u);
  // The second of each pair is the continuous turn after the discrete flip.
  EXPECT_TRUE((all[3].R).isApprox(turns[1].R * box.discrete[0].R, 1e-15));
  EXPECT_TRUE((all[3].t).isApprox(turns[1].R * box.discrete[0].t + turns[1].t, 1e-15));
}

TEST(Bop19Mssd, ShiftTurnAndSymmetry) {
  const std::vector<Eigen::Vector3f> pts = Circle(360, 0.05);
  const SE3 gt = Pose(TurnZ(0.2), Eigen::Vector3d(0.1, 0, 0.8));
  const std::vector<SE3> identity = {SE3()};
  // A shift: every point moves by it.
  EXPECT_NEAR(Mssd(pts, Pose(gt.R, gt.t + Eigen::Vector3d(0, 0.013, 0)), gt, identity), 0.013, 1e-12);
  // A turn by a about the axis: the chord 2 r sin(a / 2).
  EXPECT_NEAR(Mssd(pts, Pose(gt.R * TurnZ(0.3), gt.t), gt, identity), 2 * 0.05 * std::sin(0.15), 1e-7);
  // The same turn of a body symmetric about z: the distance to the nearest discretised turn.
  ModelInfo can;
  can.continuous.push_back({Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero()});
  const std::vector<SE3> syms = SymmetryTransformations(can);
  const double nearest = 0.3 - std::round(0.3 / kStep) * kStep;
  EXPECT_NEAR(Mssd(pts, Pose(gt.R * TurnZ(0.3), gt.t), gt, syms), 2 * 0.05 * std::sin(std::abs(nearest) / 2), 1e-7);
  EXPECT_NEAR(Mssd(pts, Pose(gt.R * TurnZ(40 * kStep), gt.t), gt, syms), 0, 1e-7);
  // A discrete flip about x maps the circle onto itself.
  ModelInfo flip;
  flip.discrete.push_back(SE3(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix(), Eigen::Vector3d::Zero()));
  const SE3 flipped = Pose(gt.R * Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix(), gt.t);
  EXPECT_NEAR(Mssd(pts, flipped, gt, SymmetryTransformations(flip)), 0, 1e-7);
  EXPECT_NEAR(Mssd(pts, flipped, gt, identity), 2 * 0.05, 1e-7);  // without it, y changes sign: 2r at most
}

TEST(Bop19Mspd, ShiftAcrossTheViewIsTheLargestImageShift) {
  // Points at depths 0.7-0.9 m; a shift of 1 cm along x moves each by fx * 0.01 / z pixels.
  std::vector<Eigen::Vector3f> pts = {{0, 0, -0.1f}, {0.02f, 0, 0}, {0, 0.03f, 0.1f}};
  const SE3 gt = Pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 0.8));
  const Intrinsics K{500, 520, 320, 240, 640, 480};
  const double nearest = 0.8 + static_cast<double>(-0.1f);  // the float point's depth
  EXPECT_NEAR(Mspd(pts, Pose(gt.R, gt.t + Eigen::Vector3d(0.01, 0, 0)), gt, {SE3()}, K), 500 * 0.01 / nearest, 1e-9);
  EXPECT_NEAR(Mspd(pts, gt, gt, {SE3()}, K), 0, 1e-12);
}

// A wall (the front face of a 10 m box) 1 m in front of a 64 x 48 camera fills the image. The
// face's two triangles meet on a diagonal through the principal point; cx - cy is not a whole
// number, so that no pixel centre lies on that shared edge (where the float reference raster
// core may leave a pixel to neither triangle).
struct Wall {
  Mesh mesh;
  Intrinsics K{50, 50, 31.3, 23.6, 64, 48};
  DepthImage test;
  Wall() {
    testing::AddBox(&mesh, Eigen::Vector3f(-5, -5, 0), Eigen::Vector3f(5, 5, 10));
    test.width = 64, test.height = 48;
    test.depth_m.assign(64 * 48, 0.f);  // no measurement anywhere: every rendered pixel is visible
  }
  SE3 At(double z) const { return Pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, z)); }
  // The share of pixels whose distance difference for a depth difference s is at least tau x diameter.
  double ShareAtLeast(double s, double tau, double diameter, bool right_half_only) const {
    int n = 0, hit = 0;
    for (int y = 0; y < 48; ++y)
      for (int x = right_half_only ? 32 : 0; x < 64; ++x) {
        const double u = (x - K.cx) / K.fx, v = (y - K.cy) / K.fy;
        ++n;
        hit += s * std::sqrt(u * u + v * v + 1) / diameter >= tau;
      }
    return static_cast<double>(hit) / n;
  }
};

const std::vector<double> kTaus = {0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.45, 0.5};

TEST(Bop19Vsd, TruthIsZeroAtEveryTau) {
  const Wall w;
  for (double e : Vsd(w.test, w.K, w.mesh, w.At(1), w.At(1), 0.1, 0.015, kTaus)) EXPECT_EQ(e, 0.0);
}

TEST(Bop19Vsd, AShiftInDepthCountsThePixelsItMovesByTauOrMore) {
  const Wall w;
  const std::vector<double> e = Vsd(w.test, w.K, w.mesh, w.At(1.021), w.At(1), 0.1, 0.015, kTaus);
  for (size_t k = 0; k < kTaus.size(); ++k) EXPECT_NEAR(e[k], w.ShareAtLeast(0.021, kTaus[k], 0.1, false), 1e-9) << kTaus[k];
  EXPECT_EQ(e[3], 1.0);  // 0.21-0.27 of the diameter everywhere
  EXPECT_EQ(e[5], 0.0);
}

// An occluder 0.5 m away over the left half: the wall behind it is not visible there, in the
// truth or in the estimate, so only the right half counts.
TEST(Bop19Vsd, APoseBehindAnOccluderCountsOnlyWhereItCanBeSeen) {
  Wall w;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 32; ++x) w.test.depth_m[static_cast<size_t>(y) * 64 + x] = 0.5f;
  for (double e : Vsd(w.test, w.K, w.mesh, w.At(1), w.At(1), 0.1, 0.015, kTaus)) EXPECT_EQ(e, 0.0);
  const std::vector<double> e = Vsd(w.test, w.K, w.mesh, w.At(1.021), w.At(1), 0.1, 0.015, kTaus);
  for (size_t k = 0; k < kTaus.size(); ++k) EXPECT_NEAR(e[k], w.ShareAtLeast(0.021, kTaus[k], 0.1, true), 1e-9) << kTaus[k];
  // An estimate far off to the side (the bounding spheres' images do not overlap): 1.
  for (double v : Vsd(w.test, w.K, w.mesh, Pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(30, 0, 1)), w.At(1), 0.1,
                      0.015, kTaus))
    EXPECT_EQ(v, 1.0);
}

Bop19Errors Errors(double mssd_m, double mspd_px, double vsd) {
  Bop19Errors e;
  e.mssd_m = mssd_m, e.mspd_px = mspd_px;
  e.vsd.assign(10, vsd);
  return e;
}

// Two instances of one object in an image, a third not a target (too little of it visible), and
// two estimates; diameter 0.1 m. Estimate 0 is nearest to instance 1 and takes it; estimate 1 then
// takes instance 0 where its error is below the threshold. The invalid instance, though nearest
// to estimate 1, is never matched.
TEST(Bop19Recall, GreedyMatchingInScoreOrderAndAverageOverThresholds) {
  std::vector<Bop19Instance> inst(3);
  for (int g = 0; g < 3; ++g) {
    inst[g].key = FrameKey{1, 1}, inst[g].obj_id = 5, inst[g].gt_index = g;
    inst[g].diameter_m = 0.1, inst[g].image_width = 640, inst[g].valid = g < 2;
  }
  inst[0].errors = {Errors(0.012, 30, 0.6), Errors(0.022, 12, 0.28)};
  inst[1].errors = {Errors(0.004, 3, 0.08), Errors(0.001, 1, 0.01)};
  inst[2].errors = {Errors(0.0001, 0.1, 0.0), Errors(0.0001, 0.1, 0.0)};
  const std::vector<const Bop19Instance*> all = {&inst[0], &inst[1], &inst[2]};
  const Bop19Summary s = Bop19Recalls(all, Bop19Options());
  EXPECT_EQ(s.targets, 2);
  // MSSD (shares of the diameter 0.04 and 0.22 after the matching): thresholds 0.05-0.5.
  // 0.05-0.2: only instance 1 -> 1/2; 0.25-0.5: both -> 1.
  EXPECT_NEAR(s.ar_mssd, (4 * 0.5 + 6 * 1.0) / 10, 1e-12);
  // MSPD (3 px and 12 px): 5, 10 -> 1/2; 15-50 -> 1.
  EXPECT_NEAR(s.ar_mspd, (2 * 0.5 + 8 * 1.0) / 10, 1e-12);
  // VSD, the same at every tau: below 0.1 estimate 0 finds nothing and estimate 1 takes
  // instance 1 (0.01); 0.1-0.25: estimate 0 takes instance 1 (0.08), estimate 1 nothing; from 0.3
  // estimate 1 also takes instance 0 (0.28). So 1/2 for five thresholds, 1 for five.
  EXPECT_NEAR(s.ar_vsd, (5 * 0.5 + 5 * 1.0) / 10, 1e-12);
  EXPECT_NEAR(s.ar, (s.ar_vsd + s.ar_mssd + s.ar_mspd) / 3, 1e-15);
  // MSPD thresholds scale with the image width: at 1280 px the errors count half.
  for (Bop19Instance& i : inst) i.image_width = 1280;
  EXPECT_NEAR(Bop19Recalls(all, Bop19Options()).ar_mspd, (1 * 0.5 + 9 * 1.0) / 10, 1e-12);
  // No estimate at all: recall 0, the targets still count.
  for (Bop19Instance& i : inst) i.errors.clear();
  const Bop19Summary none = Bop19Recalls(all, Bop19Options());
  EXPECT_EQ(none.targets, 2);
  EXPECT_EQ(none.ar, 0.0);
}

TEST(Bop19Io, ReadsModelsInfoInMetresAndRefusesBadSymmetries) {
  auto info = ReadModelsInfo(testing::BopDir() + "/models/models_info.json");
  ASSERT_TRUE(info.ok()) << info.status().ToString();
  ASSERT_EQ(info->size(), 21u);
  const ModelInfo& bowl = info->at(13);
  ASSERT_EQ(bowl.continuous.size(), 1u);
  EXPECT_NEAR(bowl.continuous[0].axis.norm(), 1, 1e-12);
  EXPECT_NEAR(bowl.continuous[0].offset_m.z(), 0.0030149, 1e-9);
  EXPECT_GT(bowl.diameter_m, 0.1);
  EXPECT_LT(bowl.diameter_m, 0.3);
  EXPECT_FALSE(info->at(16).discrete.empty());

  const std::filesystem::path dir = testing::TempDir("bop19_io");
  const auto refused = [&](const std::string& text, const std::string& message) {
    std::ofstream(dir / "info.json") << text;
    auto bad = ReadModelsInfo((dir / "info.json").string());
    ASSERT_FALSE(bad.ok()) << text;
    EXPECT_EQ(bad.status().message(), (dir / "info.json").string() + ": " + message);
  };
  refused(R"({"1": {"diameter": -3}})", "obj_id 1: 'diameter' must be a positive size in mm under 200000");
  refused(R"({"1": {"diameter": 50, "symmetries_discrete": [[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0]]}})",
          "obj_id 1: symmetries_discrete[0]: expected 16 finite numbers (a 4x4 matrix)");
  refused(R"({"1": {"diameter": 50, "symmetries_discrete": [[2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]]}})",
          "obj_id 1: symmetries_discrete[0]: R is not a rotation: max |R^T R - I| = 3, det = 2 (tolerance 0.001)");
  refused(R"({"1": {"diameter": 50, "symmetries_continuous": [{"axis": [0, 0, 0], "offset": [0, 0, 0]}]}})",
          "obj_id 1: symmetries_continuous[0]: the axis has no length");
  refused(R"({"01": {"diameter": 50}})", "key '01' is not a positive obj_id (digits, no leading zero)");

  auto targets = ReadBop19Targets(testing::BopDir() + "/test_targets_bop19.json");
  ASSERT_TRUE(targets.ok()) << targets.status().ToString();
  EXPECT_EQ(targets->size(), 20u);
  std::ofstream(dir / "targets.json") << R"([{"scene_id": 49, "im_id": 1, "obj_id": 3, "inst_count": 0}])";
  auto bad = ReadBop19Targets((dir / "targets.json").string());
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("target 0: "), std::string::npos) << bad.status().message();
}

}  // namespace
}  // namespace mcpose

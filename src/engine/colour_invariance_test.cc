// The colour term in other light: a textured box seen so that its turns are depth twins, its
// frame re-lit as another camera would see it (synth/photometric.h) or shaded by a lamp at one
// side. The colour agreement must rank the true pose above every turn in each light, and the
// whole weight must keep the ranking of the truth and its twins it had in the original light.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

#include "engine/box_scorer.h"
#include "engine/context.h"
#include "engine/twins.h"
#include "score/weight.h"
#include "mcpose/photometric.h"
#include "synthetic_mesh.h"
#include "synthetic_scene.h"

namespace mcpose::engine {
namespace {

// A printed-label-like pattern: stripes of hue and brightness that differ from face to face.
Rgba8 Pattern(int face, const Eigen::Vector3f& p) {
  const double u = 40 * p.x() + 23 * p.y() + 31 * p.z() + 1.3 * face;
  const double v = 27 * p.y() - 35 * p.z() + 0.7 * face;
  auto byte = [](double x) { return static_cast<uint8_t>(std::clamp(x, 0.0, 255.0)); };
  return {byte(130 + 90 * std::sin(u)), byte(120 + 80 * std::sin(v + 1)), byte(110 + 70 * std::sin(u - v)), 255};
}

struct Scene {
  Mesh mesh;
  SE3 T_gt;
  testing::SyntheticFrame frame;
  Detection box;
};

Scene MakeScene() {
  Scene s;
  const Eigen::Vector3f lo(-0.06f, -0.04f, -0.025f), hi(0.06f, 0.04f, 0.025f);
  s.mesh = testing::LatticeBox(lo, hi, 24, Pattern);
  s.T_gt = SE3(ExpSO3(Eigen::Vector3d(0.5, -0.4, 0.3)), Eigen::Vector3d(0.0, 0.01, 0.6));
  // The frame's colour: the pattern at the point each pixel shows (the face nearest it).
  s.frame = testing::RenderFrame(
      s.mesh, s.T_gt,
      [&](const Eigen::Vector3f& p) {
        int face = 0;
        float d = INFINITY;
        for (int f = 0; f < 6; ++f) {
          const float e = std::fabs(p[f / 2] - (f % 2 ? hi[f / 2] : lo[f / 2]));
          if (e < d) d = e, face = f;
        }
        return Pattern(face, p);
      },
      3);
  int x0 = 1 << 20, y0 = 1 << 20, x1 = -1, y1 = -1;
  for (int y = 0; y < s.frame.K.height; ++y)
    for (int x = 0; x < s.frame.K.width; ++x)
      if (s.frame.visible.values[static_cast<size_t>(y) * s.frame.K.width + x])
        x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
  s.box = Detection{1, 1, 3, 0.9, double(x0), double(y0), double(x1 - x0 + 1), double(y1 - y0 + 1)};
  return s;
}

struct Scores {
  std::vector<double> weight, colour;  // per candidate: whole weight, colour agreement A'
};

Scores Score(const Scene& s, const ColourImage& colour, const std::vector<SE3>& candidates) {
  EstimatorOptions o;
  o.engine.threads = 2;
  Context context(o);
  auto scorer = BoxScorer::Create(context, s.frame.K, s.frame.depth, s.mesh, std::span(&s.box, 1), &colour,
                                  Resolution::kFull);
  EXPECT_TRUE(scorer.ok()) << scorer.status().ToString();
  filter::ParticleSet poses;
  poses.Resize(candidates.size());
  for (size_t i = 0; i < candidates.size(); ++i)
    poses.R_cam_obj[i] = candidates[i].R, poses.t_cam_obj_m[i] = candidates[i].t, poses.box[i] = 0;
  EngineCounters counters;
  (*scorer)->Weigh(&poses, &counters);
  Scores out;
  for (size_t i = 0; i < candidates.size(); ++i) {
    out.weight.push_back(poses.weight[i]);
    out.colour.push_back(score::VisibleColourAgreement((*scorer)->last_counts()[i], o.appearance));
  }
  return out;
}

void ExpectTheRankingHolds(const Scores& r, const Scores& original) {
  // Colour alone tells the truth from each twin, by a clear margin.
  for (size_t i = 1; i < r.colour.size(); ++i) EXPECT_GT(r.colour[0], r.colour[i] + 0.05) << "twin " << i;
  // The truth still wins, and the ranking of the truth against each twin is the original's.
  for (size_t i = 1; i < r.weight.size(); ++i)
    EXPECT_EQ(r.weight[0] > r.weight[i], original.weight[0] > original.weight[i]) << "twin " << i;
}

TEST(ColourInvariance, TheTruthOutranksItsTwinsInEveryLight) {
  const Scene s = MakeScene();
  ASSERT_TRUE(s.mesh.Validate("box").ok());
  // The truth and its twins: 180-degree turns, and turns about the box's distinct axis.
  const std::vector<SE3> candidates = TwinCandidates(s.T_gt, s.mesh, 90);
  ASSERT_EQ(candidates.size(), 8u);
  const Scores original = Score(s, s.frame.colour, candidates);
  std::vector<size_t> order(candidates.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return original.weight[a] > original.weight[b]; });
  ASSERT_EQ(order[0], 0u) << "the truth must win in the original light";
  for (const char* spelling : {"exposure:0.5", "exposure:2", "white-balance:1.3,1,0.7", "white-balance:0.7,1,1.3",
                               "white-balance:1,1.3,0.7", "gamma:0.6", "gamma:1.6", "saturation:0.5",
                               "saturation:1.5", "clip:0.8", "jpeg:30", "noise:8"}) {
    SCOPED_TRACE(spelling);
    auto t = synth::ParsePhotometricTransform(spelling);
    ASSERT_TRUE(t.ok());
    auto relit = synth::ApplyPhotometric(*t, s.frame.colour, 7);
    ASSERT_TRUE(relit.ok());
    ExpectTheRankingHolds(Score(s, *relit, candidates), original);
  }
  // Shading: a light from one side, the brightness falling across the box to a fifth, the hue
  // unchanged (what a curved or turned surface shows under one lamp).
  SCOPED_TRACE("shading");
  ColourImage shaded = s.frame.colour;
  const double x0 = s.box.x, width = s.box.w;
  for (int y = 0; y < shaded.height; ++y)
    for (int x = 0; x < shaded.width; ++x) {
      const double gain = 1.0 - 0.8 * std::clamp((x - x0) / width, 0.0, 1.0);
      uint8_t* px = shaded.rgba.data() + 4 * (static_cast<size_t>(y) * shaded.width + x);
      for (int c = 0; c < 3; ++c) px[c] = static_cast<uint8_t>(std::lround(px[c] * gain));
    }
  ExpectTheRankingHolds(Score(s, shaded, candidates), original);
}

// Colour seen on a few pixels cannot overrule depth: a pose whose colour agrees perfectly on
// 25 pixels against one whose depth fits better and whose colour is unknown.
TEST(ColourTrust, ColourOnFewPixelsCannotOverruleDepth) {
  score::InlierCounts coloured, plain;
  coloured.observed = plain.observed = 1000;
  coloured.rendered = plain.rendered = 600;
  coloured.inliers = 540, plain.inliers = 590;  // the plain pose fits the depth better
  // 25 inlier pixels of known colour, model and observed equal: A = 1.
  coloured.colour.n = 25;
  for (int c = 0; c < 3; ++c) {
    for (int k = 0; k < 25; ++k) {
      const int64_t v = 40 + 7 * k + 11 * c;
      coloured.colour.m[c] += v, coloured.colour.o[c] += v;
      coloured.colour.mm[c] += v * v, coloured.colour.oo[c] += v * v, coloured.colour.mo[c] += v * v;
    }
  }
  ASSERT_DOUBLE_EQ(score::ColourAgreement(coloured.colour, 20), 1.0);
  WeightOptions w;
  AppearanceOptions trusting, untrusting;
  trusting.trust_pixels = 0;      // full say from min_pixels on
  untrusting.trust_pixels = 400;  // 25 pixels: a seventeenth of its say
  EXPECT_GT(score::WeightWithColour(coloured, 0.9, w, trusting), score::WeightWithColour(plain, 0.9, w, trusting));
  EXPECT_LT(score::WeightWithColour(coloured, 0.9, w, untrusting),
            score::WeightWithColour(plain, 0.9, w, untrusting));
  // With many pixels the same agreement is trusted again.
  score::InlierCounts many = coloured;
  many.colour.n *= 100;
  for (int c = 0; c < 3; ++c) {
    many.colour.m[c] *= 100, many.colour.o[c] *= 100;
    many.colour.mm[c] *= 100, many.colour.oo[c] *= 100, many.colour.mo[c] *= 100;
  }
  EXPECT_GT(score::WeightWithColour(many, 0.9, w, untrusting), score::WeightWithColour(plain, 0.9, w, untrusting));
  // With trust 30, colour on 25 pixels has less than half its full say.
  AppearanceOptions some;
  some.trust_pixels = 30;
  EXPECT_LT((score::VisibleColourAgreement(coloured, some) - 0.5) /
                (score::VisibleColourAgreement(coloured, trusting) - 0.5),
            0.5);
}

}  // namespace
}  // namespace mcpose::engine

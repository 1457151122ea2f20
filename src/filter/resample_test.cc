#include "filter/resample.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "core/rng.h"
#include "filter/diffuse.h"
#include "filter/particles.h"

namespace mcpose::filter {
namespace {

std::vector<double> RandomWeights(std::mt19937_64& gen, int n) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> w(n);
  for (double& x : w) x = std::pow(u(gen), 3.0);  // skewed, as weights of a converging filter
  return w;
}

// Reference: linear search over the sorted, cut, normalised CDF.
int LinearSorted(const std::vector<double>& w, double keep, double u) {
  std::vector<int> order(w.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return w[a] > w[b]; });
  order.resize(std::clamp<int>(std::ceil(keep * w.size()), 1, w.size()));
  double total = 0;
  for (int i : order) total += w[i];
  double acc = 0;
  for (size_t k = 0; k < order.size(); ++k) {
    acc += w[order[k]];
    if (acc / total > u) return order[k];
  }
  return order.back();
}

TEST(Resample, TableSearchReturnsWhatLinearSearchReturns) {
  std::mt19937_64 gen(21);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const auto w = RandomWeights(gen, 620);
    for (double keep : {1.0, 0.5, 0.1}) {
      for (int table : {1, 16, 64, 1024}) {
        CdfSampler s;
        s.Build(w, keep, table);
        for (int k = 0; k < 500; ++k) {
          const double x = u(gen);
          int64_t reads = 0;
          ASSERT_EQ(s.Draw(x, &reads), LinearSorted(w, keep, x)) << "u " << x << " table " << table;
        }
      }
    }
  }
}

TEST(Resample, FrequenciesMatchWeights) {
  std::vector<double> w = {0.5, 0.0, 2.0, 1.0, 0.25, 0.25};
  CdfSampler s;
  s.Build(w, 1.0, 8);
  std::vector<int> hits(w.size(), 0);
  const int draws = 400000;
  Rng rng(3, 4);
  for (int i = 0; i < draws; ++i) ++hits[s.Draw(rng.Uniform(), nullptr)];
  const double total = std::accumulate(w.begin(), w.end(), 0.0);
  for (size_t i = 0; i < w.size(); ++i) {
    const double p = w[i] / total;
    const double sd = std::sqrt(draws * p * (1 - p));
    EXPECT_NEAR(hits[i], draws * p, 5 * sd + 1) << i;
  }
  EXPECT_EQ(hits[1], 0);
}

TEST(Resample, TopFractionDrawsOnlyTheBest) {
  std::mt19937_64 gen(22);
  const auto w = RandomWeights(gen, 100);
  CdfSampler s;
  s.Build(w, 0.1, 16);
  std::vector<double> sorted = w;
  std::sort(sorted.rbegin(), sorted.rend());
  Rng rng(1, 1);
  for (int i = 0; i < 10000; ++i) EXPECT_GE(w[s.Draw(rng.Uniform(), nullptr)], sorted[9]);
}

TEST(Resample, ZeroWeightsDrawUniformly) {
  std::vector<double> w(10, 0.0);
  CdfSampler s;
  s.Build(w, 1.0, 4);
  std::vector<int> hits(10, 0);
  Rng rng(5, 5);
  for (int i = 0; i < 100000; ++i) ++hits[s.Draw(rng.Uniform(), nullptr)];
  for (int h : hits) EXPECT_NEAR(h, 10000, 500);
}

TEST(Resample, TableNeedsFewReadsPerDraw) {
  std::mt19937_64 gen(23);
  const auto w = RandomWeights(gen, 620);
  CdfSampler s;
  s.Build(w, 1.0, 64);
  int64_t reads = 0;
  Rng rng(9, 9);
  for (int i = 0; i < 10000; ++i) s.Draw(rng.Uniform(), &reads);
  EXPECT_GE(reads / 10000.0, 2.0);  // the table entry and at least one CDF entry
  EXPECT_LT(reads / 10000.0, 20.0);
}

TEST(Particles, AllocationFollowsScores) {
  EXPECT_EQ(AllocateSamples({1.0}, 620), std::vector<int>({620}));
  EXPECT_EQ(AllocateSamples({0.9, 0.3}, 620), std::vector<int>({465, 155}));
  const auto c = AllocateSamples({0.7, 0.2, 0.2, 0.55}, 620);
  EXPECT_EQ(std::accumulate(c.begin(), c.end(), 0), 620);
  EXPECT_EQ(AllocateSamples({1.0, 1.0, 1.0}, 5), std::vector<int>({2, 2, 1}));
}

TEST(Particles, UniformRotationIsUniform) {
  // For uniform rotations E[R] = 0 and the angle has density (1 - cos θ) / π.
  Rng rng(1, 2);
  Eigen::Matrix3d mean = Eigen::Matrix3d::Zero();
  const int n = 100000;
  int small = 0;
  for (int i = 0; i < n; ++i) {
    const Eigen::Matrix3d R = UniformRotation(rng.Uniform(), rng.Uniform(), rng.Uniform());
    ASSERT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 1e-9);
    mean += R / n;
    small += LogSO3(R).norm() < M_PI / 2;
  }
  EXPECT_LT(mean.cwiseAbs().maxCoeff(), 0.01);
  // P(θ < π/2) = (θ - sin θ) / π at π/2 = 0.1817.
  EXPECT_NEAR(small / double(n), (M_PI / 2 - 1) / M_PI, 0.005);
}

TEST(Diffuse, MeanAndCovarianceMatchSigmas) {
  const Eigen::Matrix3d R0 = ExpSO3(Eigen::Vector3d(0.3, -0.2, 1.0));
  const Eigen::Vector3d t0(0.1, -0.05, 0.8);
  const double sr = 0.05, st = 0.01;
  const int n = 50000;
  Eigen::Vector3d mr = Eigen::Vector3d::Zero(), mt = Eigen::Vector3d::Zero();
  Eigen::Matrix3d cr = Eigen::Matrix3d::Zero(), ct = Eigen::Matrix3d::Zero();
  for (int i = 0; i < n; ++i) {
    Rng rng(4, 4, 0, i);
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    Diffuse(R0, t0, sr, st, rng, &R, &t);
    const Eigen::Vector3d w = LogSO3(R * R0.transpose()), d = t - t0;
    mr += w / n, mt += d / n;
    cr += w * w.transpose() / n, ct += d * d.transpose() / n;
  }
  EXPECT_LT(mr.norm(), 3 * sr / std::sqrt(n) * 2);
  EXPECT_LT(mt.norm(), 3 * st / std::sqrt(n) * 2);
  EXPECT_LT((cr - sr * sr * Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 0.05 * sr * sr);
  EXPECT_LT((ct - st * st * Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 0.05 * st * st);
}

// A flip turns the pose 180 degrees about one model axis through `center`: the centre stays put
// in the camera frame, the axis keeps its direction, the other two reverse, and two flips about
// the same axis give the pose back.
TEST(Flip, TurnsHalfAboutAModelAxisThroughTheCentre) {
  const Eigen::Matrix3d R0 = ExpSO3(Eigen::Vector3d(0.3, -0.2, 1.0));
  const Eigen::Vector3d t0(0.1, -0.05, 0.8), c(0.01, -0.02, 0.03);
  for (int axis = 0; axis < 3; ++axis) {
    Eigen::Matrix3d R = R0;
    Eigen::Vector3d t = t0;
    Flip(axis, c, &R, &t);
    EXPECT_LT((R * c + t - (R0 * c + t0)).norm(), 1e-12) << axis;
    EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
    for (int k = 0; k < 3; ++k) {
      const double sign = k == axis ? 1 : -1;
      EXPECT_LT((R.col(k) - sign * R0.col(k)).norm(), 1e-12) << axis << " " << k;
    }
    EXPECT_NEAR(LogSO3(R0.transpose() * R).norm(), M_PI, 1e-9);
    Flip(axis, c, &R, &t);
    EXPECT_LT((R - R0).norm(), 1e-12);
    EXPECT_LT((t - t0).norm(), 1e-12);
  }
}

}  // namespace
}  // namespace mcpose::filter

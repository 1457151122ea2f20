#include "bench/naive_cdf.h"

#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "core/rng.h"
#include "filter/resample.h"

namespace mcpose::bench {
namespace {

// The naive search draws what the table draws (same distribution, same sample for the same u
// when the kept samples are already in weight order) and its read count is what it reads;
// on skewed weights it reads far more than the table.
TEST(NaiveCdf, ReadsAreCountedExactlyAndFarExceedTheTables) {
  std::mt19937_64 gen(23);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::vector<double> w(620);
  for (double& x : w) x = std::pow(uni(gen), 3.0);
  NaiveCdf naive;
  naive.Build(w, 1.0);
  filter::CdfSampler table;
  table.Build(w, 1.0, 64);
  int64_t reads = 0, naive_reads = 0;
  Rng rng(9, 9);
  for (int i = 0; i < 10000; ++i) {
    const double u = rng.Uniform();
    table.Draw(u, &reads);
    int64_t linear = 0;
    naive.Draw(u, &linear);
    ASSERT_EQ(naive.Reads(u), linear) << u;
    naive_reads += linear;
  }
  for (double u : {0.0, std::nextafter(1.0, 0.0)}) {  // the ends
    int64_t linear = 0;
    naive.Draw(u, &linear);
    EXPECT_EQ(naive.Reads(u), linear) << u;
  }
  EXPECT_LT(reads / 10000.0, 20.0);
  EXPECT_GT(naive_reads / 10000.0, 200.0);
}

TEST(NaiveCdf, DrawsOnlyTheKeptTopFraction) {
  const std::vector<double> w = {0.1, 0.9, 0.2, 0.8};
  NaiveCdf naive;
  naive.Build(w, 0.5);  // keeps samples 1 and 3
  Rng rng(1, 2);
  for (int i = 0; i < 1000; ++i) {
    const int s = naive.Draw(rng.Uniform(), nullptr);
    EXPECT_TRUE(s == 1 || s == 3) << s;
  }
}

}  // namespace
}  // namespace mcpose::bench

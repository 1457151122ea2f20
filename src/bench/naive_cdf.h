// The resampler the paper's CDF table replaces, for `mcpose bench`'s comparison: a linear
// search of the cumulative weights in sample order (the same top-fraction cut), from the first
// entry. It draws from the same distribution as filter::CdfSampler; only the reads differ.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace mcpose::bench {

class NaiveCdf {
 public:
  // The cumulative weights of `weights` in index order, counting only the best
  // keep_top_fraction of them (as CdfSampler cuts), normalised to end at 1.
  void Build(std::span<const double> weights, double keep_top_fraction);
  // The sample a linear search draws for u in [0, 1); adds its reads to *reads.
  int Draw(double u, int64_t* reads) const;
  // The reads Draw(u) makes, found by binary search (the cumulative weights do not decrease).
  int64_t Reads(double u) const;

 private:
  std::vector<double> cdf_;
};

}  // namespace mcpose::bench

#include "bench/naive_cdf.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/check.h"

namespace mcpose::bench {

void NaiveCdf::Build(std::span<const double> weights, double keep_top_fraction) {
  MCPOSE_CHECK(!weights.empty());
  const int n = static_cast<int>(weights.size());
  std::vector<int> order(static_cast<size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return weights[a] > weights[b]; });
  const int keep = std::clamp(static_cast<int>(std::ceil(keep_top_fraction * n)), 1, n);
  std::vector<char> kept(static_cast<size_t>(n), 0);
  double total = 0;
  for (int k = 0; k < keep; ++k) kept[order[k]] = 1, total += weights[order[k]];
  const bool uniform = !(total > 0);
  cdf_.assign(static_cast<size_t>(n), 0.0);
  double acc = 0;
  for (int i = 0; i < n; ++i) {
    if (kept[i]) acc += uniform ? 1.0 : weights[i];
    cdf_[i] = acc;
  }
  for (double& c : cdf_) c /= acc;
}

int NaiveCdf::Draw(double u, int64_t* reads) const {
  const int n = static_cast<int>(cdf_.size());
  int i = 0;
  int64_t r = 0;
  while (true) {
    ++r;
    if (cdf_[i] > u || i == n - 1) break;
    ++i;
  }
  if (reads) *reads += r;
  return i;
}

int64_t NaiveCdf::Reads(double u) const {
  // Draw stops at the first cdf > u, or at the last entry.
  const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  const int64_t n = static_cast<int64_t>(cdf_.size());
  return std::min<int64_t>(it - cdf_.begin(), n - 1) + 1;
}

}  // namespace mcpose::bench

#include "filter/resample.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/check.h"

namespace mcpose::filter {

void CdfSampler::Build(std::span<const double> weights, double keep_top_fraction, int table_size) {
  MCPOSE_CHECK(!weights.empty());
  MCPOSE_CHECK_GE(table_size, 1);
  const int n = static_cast<int>(weights.size());

  // 1-2. Sorted indices, heaviest first, cut to the top fraction.
  order_.resize(n);
  std::iota(order_.begin(), order_.end(), 0);
  std::stable_sort(order_.begin(), order_.end(),
                   [&](int a, int b) { return weights[a] > weights[b]; });
  const int keep = std::clamp(static_cast<int>(std::ceil(keep_top_fraction * n)), 1, n);
  order_.resize(keep);

  // 3. CDF over the kept samples; uniform if they carry no weight.
  double total = 0;
  for (int i : order_) total += weights[i];
  const bool uniform = !(total > 0);
  cdf_.resize(keep);
  double acc = 0;
  for (int k = 0; k < keep; ++k) {
    acc += uniform ? 1.0 : weights[order_[k]];
    cdf_[k] = acc;
  }
  for (double& c : cdf_) c /= acc;
  cdf_.back() = 1.0;

  // Coarse table: first position whose cumulative weight exceeds k / table_size.
  table_.resize(table_size);
  int pos = 0;
  for (int k = 0; k < table_size; ++k) {
    const double threshold = static_cast<double>(k) / table_size;
    while (pos < keep - 1 && cdf_[pos] <= threshold) ++pos;
    table_[k] = pos;
  }
}

int CdfSampler::Draw(double u, int64_t* reads) const {
  const int table_size = static_cast<int>(table_.size());
  const int k = std::min(table_size - 1, static_cast<int>(u * table_size));
  int pos = table_[k];
  int64_t r = 1;  // the table entry
  // Fine search: first position with cdf > u. The table guarantees cdf[pos - 1] <= u.
  while (true) {
    ++r;
    if (cdf_[pos] > u || pos == static_cast<int>(cdf_.size()) - 1) break;
    ++pos;
  }
  if (reads) *reads += r;
  return order_[pos];
}

}  // namespace mcpose::filter

#include "filter/particles.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <Eigen/Geometry>

namespace mcpose::filter {

Eigen::Matrix3d UniformRotation(double u1, double u2, double u3) {
  const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
  const double t1 = 2.0 * M_PI * u2, t2 = 2.0 * M_PI * u3;
  Eigen::Quaterniond q(b * std::cos(t2), a * std::sin(t1), a * std::cos(t1), b * std::sin(t2));
  return q.normalized().toRotationMatrix();
}

std::vector<int> AllocateSamples(const std::vector<double>& scores, int total) {
  const double sum = std::accumulate(scores.begin(), scores.end(), 0.0);
  std::vector<int> counts(scores.size(), 0);
  std::vector<std::pair<double, size_t>> remainders;
  int assigned = 0;
  for (size_t i = 0; i < scores.size(); ++i) {
    const double exact = total * scores[i] / sum;
    counts[i] = static_cast<int>(std::floor(exact));
    assigned += counts[i];
    remainders.emplace_back(exact - counts[i], i);
  }
  // Largest remainders first; equal remainders go to the lower index.
  std::stable_sort(remainders.begin(), remainders.end(),
                   [](const auto& l, const auto& r) { return l.first > r.first; });
  for (size_t k = 0; assigned < total; ++k, ++assigned) ++counts[remainders[k % remainders.size()].second];
  return counts;
}

}  // namespace mcpose::filter

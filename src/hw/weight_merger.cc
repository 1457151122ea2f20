#include "hw/weight_merger.h"

#include <algorithm>
#include <cmath>

namespace mcpose::hw {

namespace {

uint32_t Q16(double v) {
  return static_cast<uint32_t>(std::lround(std::clamp(v, 0.0, 1.0) * (1 << kWeightFracBits)));
}

}  // namespace

WeightCoefficients QuantizeWeight(double a, double b, double c, double score, bool occlusion_aware) {
  return {Q16(a), Q16(b), Q16(c), Q16(score), occlusion_aware};
}

uint32_t MergedWeight(const Counts& n, int32_t observed, const WeightCoefficients& w) {
  const int64_t inliers = n.inliers;
  const int64_t rendered = w.occlusion_aware ? int64_t{n.rendered} - n.occluded : n.rendered;
  const int64_t recall = observed > 0 ? int64_t{w.a} * inliers / observed : 0;
  const int64_t precision = rendered > 0 ? int64_t{w.b} * inliers / rendered : 0;
  const int64_t detector = (int64_t{w.c} * w.score) >> kWeightFracBits;
  return static_cast<uint32_t>(recall + precision + detector);
}

}  // namespace mcpose::hw

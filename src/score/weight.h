// Step 3 of the filter: a sample's weight from its inlier counts and its box's score.
#pragma once

#include "mcpose/options.h"
#include "score/inlier.h"

namespace mcpose::score {

// w = a * N / N_b + b * N / N_r + c * score; a term with a zero denominator is 0. With
// `occlusion_aware`, rendered pixels hidden behind observed surfaces do not count against the
// precision term: N_r becomes N_r - occluded.
inline double Weight(const InlierCounts& n, double score, double a, double b, double c,
                     bool occlusion_aware = false) {
  const int32_t rendered = occlusion_aware ? n.rendered - n.occluded : n.rendered;
  const double recall = n.observed > 0 ? static_cast<double>(n.inliers) / n.observed : 0.0;
  const double precision = rendered > 0 ? static_cast<double>(n.inliers) / rendered : 0.0;
  return a * recall + b * precision + c * score;
}

inline double Weight(const InlierCounts& n, double score, const WeightOptions& w) {
  return Weight(n, score, w.a, w.b, w.c, w.occlusion_aware);
}

}  // namespace mcpose::score

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

// The colour agreement the weight uses: ColourAgreement of the depth inliers drawn towards
// neutral by the share of the rendered object whose depth does not agree,
// A' = 0.5 + (A - 0.5) N / N_r: colour speaks for a pose only as far as its depth does. The
// depth terms excuse hidden pixels (an object partly behind another is not punished for it);
// without the pull, a pose sunk into the table, its few visible pixels matching well, could
// outweigh the object in plain view, and a pose floating in front of the observed surface (a
// bowl turned upside down above the real one, whose rendered dome hides nothing) could outweigh
// the real bowl half hidden by what lies in it.
// It is drawn towards neutral also by how few pixels carry it, by n / (n + trust_pixels) for n
// the depth inliers of known colour: a correlation over a few pixels is mostly noise, and must
// not overrule the depth and the box (trust_pixels 0: no such pull).
inline double VisibleColourAgreement(const InlierCounts& n, int min_pixels, double trust_pixels = 0,
                                     double hue_first_levels = 0) {
  const double a = ColourAgreement(n.colour, min_pixels, hue_first_levels);
  const double visible = n.rendered > 0 ? static_cast<double>(n.inliers) / n.rendered : 0.0;
  const double pixels = static_cast<double>(n.colour.n);
  const double trust = trust_pixels > 0 ? pixels / (pixels + trust_pixels) : 1.0;
  return kNeutralAgreement + (a - kNeutralAgreement) * visible * trust;
}
inline double VisibleColourAgreement(const InlierCounts& n, const AppearanceOptions& appearance) {
  return VisibleColourAgreement(n, appearance.min_pixels, appearance.trust_pixels, appearance.hue_first_levels);
}

// w = (1 - d) (a N / N_b + b N / N_r + c score) + d A', d = appearance.weight.
inline double WeightWithColour(const InlierCounts& n, double score, const WeightOptions& w,
                               const AppearanceOptions& appearance) {
  return (1 - appearance.weight) * Weight(n, score, w) +
         appearance.weight * VisibleColourAgreement(n, appearance);
}

}  // namespace mcpose::score

// The paper's weight merger in integer arithmetic: each sample's weight from its raster core's
// counts, w = a N / N_b + b N / N_r + c s, in Q16 (docs/hardware.md). hw/rtl/weight_merger.sv
// computes exactly this.
#pragma once

#include <cstdint>

#include "hw/raster_core.h"

namespace mcpose::hw {

inline constexpr int kWeightFracBits = 16;

// The coefficients a, b, c and the box's detector score s in Q16 (each in [0, 2^16]), and
// whether N_r leaves out the rendered pixels hidden behind an observed surface.
struct WeightCoefficients {
  uint32_t a = 0, b = 0, c = 0;
  uint32_t score = 0;
  bool occlusion_aware = false;
};
// Rounds a, b, c and the score (each clamped to [0, 1]) to Q16.
WeightCoefficients QuantizeWeight(double a, double b, double c, double score, bool occlusion_aware);

// floor(a N / N_b) + floor(b N / N_r) + floor(c s / 2^16), Q16; a term with a zero denominator
// is 0, as in score::Weight. N_r is rendered - occluded with occlusion_aware. observed: N_b.
uint32_t MergedWeight(const Counts& n, int32_t observed, const WeightCoefficients& w);

}  // namespace mcpose::hw

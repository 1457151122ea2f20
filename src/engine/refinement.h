// Refinement of an estimate: its pose aligned to the observed depth in its box
// (refine/align.h), kept only when that does not lower its full-resolution weight.
#pragma once

#include "engine/box_scorer.h"
#include "mcpose/estimator.h"
#include "refine/align.h"

namespace mcpose::engine {

// The alignment settings of the options, with `iterations` steps.
refine::AlignOptions AlignSettings(const RefineOptions& options, int iterations);

// Aligns `estimate`'s pose in its chosen box and keeps the result when `full` (a
// full-resolution scorer of that box alone, Resolution::kFull) weighs it at least as high as
// the pose it started from. Fills estimate.refine.
ObjectEstimate RefineEstimate(const RefineOptions& options, BoxScorer& full, const DepthImage& depth,
                              ObjectEstimate estimate);

}  // namespace mcpose::engine

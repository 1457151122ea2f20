// What an analysis::Scorer holds: the estimator's engine context.
#pragma once

#include "engine/context.h"
#include "mcpose/analysis/scorer.h"

namespace mcpose::analysis {

struct Scorer::Impl {
  explicit Impl(const EstimatorOptions& options) : context(options) {}
  engine::Context context;
};

}  // namespace mcpose::analysis

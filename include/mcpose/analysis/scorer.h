// The estimator's scoring machinery for the analyses (its raster cores, threads, level of detail
// and colour term, as EstimatorOptions set them), made once and reused for many instances.
#pragma once

#include <memory>

#include "mcpose/options.h"

namespace mcpose::analysis {

class Scorer {
 public:
  explicit Scorer(const EstimatorOptions& options);
  ~Scorer();
  Scorer(const Scorer&) = delete;
  Scorer& operator=(const Scorer&) = delete;

  const EstimatorOptions& options() const;

  struct Impl;  // src/analysis/scorer.h
  Impl& impl() { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace mcpose::analysis

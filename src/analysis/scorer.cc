#include "analysis/scorer.h"

namespace mcpose::analysis {

Scorer::Scorer(const EstimatorOptions& options) : impl_(std::make_unique<Impl>(options)) {}
Scorer::~Scorer() = default;
const EstimatorOptions& Scorer::options() const { return impl_->context.options(); }

}  // namespace mcpose::analysis

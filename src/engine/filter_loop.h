// The paper's sequential Monte-Carlo loop for one object class in one image.
#pragma once

#include <cstdint>
#include <functional>

#include "engine/box_scorer.h"
#include "filter/particles.h"
#include "mcpose/estimator.h"
#include "mcpose/options.h"

namespace mcpose::engine {

// Called after each iteration's weights, with the iteration's index and its weighted samples
// (`mcpose bench` reads them to compare resamplers); may be empty.
using IterationObserver = std::function<void(int iteration, const filter::ParticleSet& weighted)>;

// The samples of a generation after the first that pass to the next unchanged (the elite):
// round(options.resample.elite_share * generation), at most `generation`. The others are drawn.
int EliteCount(const EstimatorOptions& options, int generation);

// Initialize (or start from `start`, samples with their boxes), then score, weigh, resample
// and diffuse until the mean weight exceeds tau or max_iterations; the answer is the
// best-weighted sample ever seen. The first generation holds options.init.wide * samples
// samples (without `start`), every later one `samples` (start's size with it). Depends on
// (options.seed, stream_id) only, never on the thread count.
ObjectEstimate RunFilter(BoxScorer& scorer, const EstimatorOptions& options, ThreadPool& pool, uint64_t stream_id,
                         const IterationObserver& observer = {}, const filter::ParticleSet* start = nullptr);

}  // namespace mcpose::engine

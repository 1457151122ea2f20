// EstimatorOptions, TrackerOptions and EngineCounters as JSON, the one place that names their fields for
// files (`mcpose estimate --out-json`, `mcpose track --out-json`, `mcpose bench --json`).
#pragma once

#include <nlohmann/json.hpp>

#include "mcpose/estimator.h"
#include "mcpose/options.h"
#include "mcpose/tracker.h"

namespace mcpose::io {

// {"samples", "max_iterations", "tau", "seed", "init": {...}, "weight": {...}, "resample": {...},
//  "diffusion": {...}, "engine": {...}}, field names as in options.h.
nlohmann::json OptionsToJson(const EstimatorOptions& options);
nlohmann::json CountersToJson(const EngineCounters& counters);
// The tracker's fields as in tracker.h, its single-frame options under "estimator".
nlohmann::json TrackerOptionsToJson(const TrackerOptions& options);

}  // namespace mcpose::io

// EstimatorOptions, TrackerOptions and EngineCounters as JSON, the one place that names their fields for
// files (`mcpose estimate --out-json`, `mcpose track --out-json`, `mcpose bench --json`).
#pragma once

#include <nlohmann/json.hpp>

#include "mcpose/estimator.h"
#include "mcpose/options.h"
#include "mcpose/status.h"
#include "mcpose/tracker.h"

namespace mcpose::io {

// {"samples", "max_iterations", "tau", "seed", "max_instances", "init": {...}, "weight": {...},
//  "resample": {...}, "diffusion": {...}, "appearance": {...}, "refine": {...}, "engine": {...}}:
// every field of the options table (mcpose/option_table.h) under its key, numbers and switches
// as numbers and booleans, enums by name.
nlohmann::json OptionsToJson(const EstimatorOptions& options);
// The options of such JSON: each field it names set (the others keep their defaults), then
// checked (IsValid). Errors name the key: an unknown one, a wrong type, a value out of bounds.
StatusOr<EstimatorOptions> OptionsFromJson(const nlohmann::json& json);
// Where a field of the options table lies in that JSON: "refine.tukey_m" -> /refine/tukey_m.
nlohmann::json::json_pointer OptionPointer(const char* key);
nlohmann::json CountersToJson(const EngineCounters& counters);
// The tracker's fields as in tracker.h, its single-frame options under "estimator".
nlohmann::json TrackerOptionsToJson(const TrackerOptions& options);

}  // namespace mcpose::io

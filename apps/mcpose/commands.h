// The mcpose command-line tool: parsing and printing only; all work is in the library.
#pragma once

#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "mcpose/estimator.h"

#include "mcpose/status.h"

namespace mcpose::cli {

// Each Add* registers a subcommand; its callback stores the command's Status in *status.
void AddEstimateCommand(CLI::App& app, Status* status);
void AddDetectionsFromGtCommand(CLI::App& app, Status* status);
void AddEvalCommand(CLI::App& app, Status* status);
void AddBenchCommand(CLI::App& app, Status* status);
void AddAmbiguityCommand(CLI::App& app, Status* status);
void AddTurnProfileCommand(CLI::App& app, Status* status);

// The engine counters of one object as JSON (estimate --out-json, bench --json).
nlohmann::json CountersJson(const EngineCounters& counters);

// Writes `text` to `path` through a temporary file and a rename: no partial file on error.
Status WriteFileAtomically(const std::string& path, const std::string& text);
// Ok if a file could be created at `path` (its folder exists and is writable).
Status CheckWritable(const std::string& path);

// --simd-target (estimate, bench): caps the runtime SIMD dispatch; empty = the best target.
void AddSimdTargetOption(CLI::App* cmd, std::string* name);
Status ApplySimdTarget(const std::string& name);

}  // namespace mcpose::cli

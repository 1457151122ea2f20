// The options tables (mcpose/option_table.h) as command-line flags (CLI11): what `mcpose
// estimate` and `mcpose track` take, and what the Python package's keyword options are parsed
// with, so that a bad option gets the same message everywhere.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "mcpose/option_table.h"
#include "mcpose/options.h"
#include "mcpose/status.h"
#include "mcpose/tracker.h"

namespace mcpose {

// The estimator's flags of one command, bound to `options`; Finish() after parsing.
struct EstimatorFlags {
  EstimatorOptions options;
  std::map<std::string, std::string> text;          // enum and on|off fields by key, as given
  std::map<std::string, const CLI::Option*> given;  // the switches of the engine's features
  std::vector<double> weights;                      // --weights a b c

  // After parsing: applies the enum and on|off fields and --weights; the engine
  // features not given on the command line are turned off where the chosen backend and LOD
  // setting cannot use them (so `--engine scalar` needs nothing else), while one given
  // explicitly that has no effect is an error; then validates (a --simd-target this CPU lacks
  // included). Errors name the flag or the option field.
  Status Finish();
};

// Adds the flags of the table's fields in `groups` (OptionGroup bits), bound to `flags`.
void AddEstimatorFlags(CLI::App* cmd, unsigned groups, EstimatorFlags* flags);
// The tracker's own flags (TrackerOptionFields), bound to `options`.
void AddTrackerFlags(CLI::App* cmd, TrackerOptions* options);

// The estimator's options from `args` ("--samples", "300", "--no-resolve-twins", ...), parsed
// as `mcpose estimate` parses its flags: the same defaults, checks and one-line messages; over
// `base` (default: the defaults). For front ends other than the command line (Python).
StatusOr<EstimatorOptions> ParseEstimatorOptions(const std::vector<std::string>& args,
                                                 const EstimatorOptions& base = EstimatorOptions{});
// The tracker's options from its flags and the estimator's (all but --max-instances).
StatusOr<TrackerOptions> ParseTrackerOptions(const std::vector<std::string>& args);
// Whether estimator flag `name` ("resolve-twins") is a switch (--name / --no-name) rather than
// an option taking a value; false for an unknown name.
bool IsEstimatorSwitch(const std::string& name);

// The check of every --seed: decimal digits that fit 64 bits. CLI11 alone would wrap -1 and
// 2^64 around to other seeds.
const CLI::Validator& SeedCheck();

}  // namespace mcpose

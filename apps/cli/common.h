// What the command-line programs (mcpose, mcpose-tools) share: the estimator's flags, each
// registered once, and safe output files.
#pragma once

#include <initializer_list>
#include <map>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "mcpose/dataset.h"
#include "mcpose/detection.h"
#include "mcpose/option_table.h"
#include "mcpose/options.h"
#include "mcpose/tracker.h"
#include "mcpose/status.h"

namespace mcpose::cli {

// The groups of estimator flags a command takes (the table's groups, mcpose/option_table.h).
enum FlagGroup : unsigned {
  kSamplingFlags = kSamplingOptions,      // --samples --seed
  kStoppingFlags = kStoppingOptions,      // --iterations --tau
  kWeightFlags = kWeightOptions,          // --inlier --eps --weights --[no-]occlusion-aware --box-fit
  kSearchFlags = kSearchOptions,          // initialization, resampling and diffusion
  kEngineFlags = kEngineOptions,          // --engine, its features, --threads, --simd-target
  kAppearanceFlags = kAppearanceOptions,  // --appearance and the colour term
  kRefineFlags = kRefineOptions,          // --refine ...
  kInstanceFlags = kInstanceOptions,      // --max-instances (estimation jobs, not tracking)
  kAllEstimatorFlags = kAllOptions,
};

// The estimator's options as flags, one per field of the options table (plus --weights for
// a b c, and --simd-target): parsed into `options` and finished by Finish().
struct EstimatorFlags {
  EstimatorOptions options;
  std::map<std::string, std::string> text;          // enum and on|off fields by key, as given
  std::map<std::string, const CLI::Option*> given;  // the switches of the engine's features
  std::string simd_target;
  std::vector<double> weights;

  // After parsing: applies the enum and on|off fields, --weights and --simd-target; the engine
  // features not given on the command line are turned off where the chosen backend and LOD
  // setting cannot use them (so `--engine scalar` needs nothing else), while one given
  // explicitly that has no effect is an error; then validates. Errors name the flag or the
  // option field.
  Status Finish();
};

// Registers the flags of `groups` on `cmd`, with their defaults in the help.
void AddEstimatorFlags(CLI::App* cmd, unsigned groups, EstimatorFlags* flags);

// The estimator's options from `args` ("--samples", "300", "--no-resolve-twins", ...), parsed
// as `mcpose estimate` parses its flags: the same defaults, checks and one-line messages. For
// front ends other than the command line (the Python package).
// `base`: the options before the flags (default: the defaults).
StatusOr<EstimatorOptions> ParseEstimatorOptions(const std::vector<std::string>& args,
                                                 const EstimatorOptions& base = EstimatorOptions{});
// The tracker's own flags (--track-samples ... --lost-visible), with their defaults in the help;
// `mcpose track` adds the estimator's beside them.
void AddTrackerFlags(CLI::App* cmd, TrackerOptions* options);
// The tracker's options from `args`: its own flags and the estimator's, parsed and checked as
// `mcpose track` parses them. For the Python package.
StatusOr<TrackerOptions> ParseTrackerOptions(const std::vector<std::string>& args);
// Whether estimator flag `name` ("resolve-twins") is a switch (--name / --no-name) rather than
// an option taking a value; false for an unknown name.
bool IsEstimatorSwitch(const std::string& name);

// Removes the output file at `path` (if any; empty: nothing), when a later output failed.
void RemoveOutput(const std::string& path);

// The check of every --seed: decimal digits that fit 64 bits. CLI11 alone would wrap -1 and
// 2^64 around to other seeds.
const CLI::Validator& SeedCheck();

// Ok if a file could be created at `path` (its folder exists and is writable).
Status CheckWritable(const std::string& path);

// A command's file argument: its flag and the path given (empty: not given).
struct PathArg {
  const char* flag;
  const std::string& path;
};
// Ok unless an output names the same file as an input or as another output (through any
// spelling, link or hard link); checked before any work, so that no run overwrites its own input.
Status CheckOutputsDistinct(std::initializer_list<PathArg> inputs, std::initializer_list<PathArg> outputs);
// Ok unless an output would overwrite what the dataset holds: an existing file or folder inside
// its root or models folder (any of them may be read), or a folder holding either.
Status CheckOutputsOutsideDataset(const Dataset& dataset, std::initializer_list<PathArg> outputs);

// --min-score: drops the detections whose score is below `min_score` (0, the default, keeps every
// box, as the paper prescribes: the estimator weighs each box by its score instead). Refuses a
// value outside [0, 1], and a threshold no detection of `source` meets.
Status KeepScoresAtLeast(double min_score, const std::string& source, std::vector<Detection>* detections);

// The SIMD target the kernels dispatch to now, and those this build and CPU offer.
std::string ActiveSimdTarget();
std::string SimdTargets();

}  // namespace mcpose::cli

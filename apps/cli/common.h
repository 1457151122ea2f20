// What the command-line programs (mcpose, mcpose-tools) share: the flag groups of the options
// table (the flags themselves: mcpose/option_flags.h) and safe output files.
#pragma once

#include <initializer_list>
#include <map>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "mcpose/dataset.h"
#include "mcpose/detection.h"
#include "mcpose/option_flags.h"
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

// Removes the output file at `path` (if any; empty: nothing), when a later output failed.
void RemoveOutput(const std::string& path);

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

// The SIMD targets this build and CPU offer, best first.
std::string SimdTargets();

}  // namespace mcpose::cli

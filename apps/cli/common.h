// What the command-line programs (mcpose, mcpose-tools) share beside the option flags
// (mcpose/option_flags.h, whose groups are the table's OptionGroup): safe output files.
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

}  // namespace mcpose::cli

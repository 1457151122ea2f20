// The mcpose command-line tool: parsing and printing only; all work is in the library.
#pragma once

#include <CLI/CLI.hpp>

#include "mcpose/status.h"

namespace mcpose::cli {

// Each Add* registers a subcommand; its callback stores the command's Status in *status.
void AddEstimateCommand(CLI::App& app, Status* status);
void AddDetectionsFromGtCommand(CLI::App& app, Status* status);
void AddEvalCommand(CLI::App& app, Status* status);
void AddBenchCommand(CLI::App& app, Status* status);
void AddCaptureCommand(CLI::App& app, Status* status);
void AddTrackCommand(CLI::App& app, Status* status);
void AddReportCommand(CLI::App& app, Status* status);
void AddSynthCommand(CLI::App& app, Status* status);

}  // namespace mcpose::cli

// mcpose-tools: diagnostics for developers, not part of estimating poses (README, "Tools").
#pragma once

#include <cstdio>

#include <CLI/CLI.hpp>

#include "mcpose/status.h"

namespace mcpose::tools {

// Progress over a dataset's frames on stderr ("frames 12/26"), a line of its own when done.
inline void PrintFrameProgress(int done, int total) {
  std::fprintf(stderr, "\rframes %d/%d", done, total);
  if (done == total) std::fprintf(stderr, "\n");
}

void AddAmbiguityCommand(CLI::App& app, Status* status);
void AddTurnProfileCommand(CLI::App& app, Status* status);
void AddRefineFloorCommand(CLI::App& app, Status* status);
void AddMissesCommand(CLI::App& app, Status* status);
void AddRelightCommand(CLI::App& app, Status* status);
void AddTwinMarginCommand(CLI::App& app, Status* status);
void AddHwWorkloadCommand(CLI::App& app, Status* status);

}  // namespace mcpose::tools

// mcpose-tools: diagnostics for developers, not part of estimating poses (README, "Tools").
#pragma once

#include <CLI/CLI.hpp>

#include "mcpose/status.h"

namespace mcpose::tools {

void AddAmbiguityCommand(CLI::App& app, Status* status);
void AddTurnProfileCommand(CLI::App& app, Status* status);
void AddRefineFloorCommand(CLI::App& app, Status* status);
void AddMissesCommand(CLI::App& app, Status* status);

}  // namespace mcpose::tools

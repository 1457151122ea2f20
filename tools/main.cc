#include <cstdio>
#include <exception>
#include <new>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "mcpose/option_table.h"
#include "tools.h"

int main(int argc, char** argv) {
  CLI::App app{
      "mcpose-tools: diagnostics of the likelihood, the search and the refinement on real frames (for developers of mcpose)."};
  app.require_subcommand(1);
  mcpose::Status status;
  mcpose::tools::AddAmbiguityCommand(app, &status);
  mcpose::tools::AddTurnProfileCommand(app, &status);
  mcpose::tools::AddRefineFloorCommand(app, &status);
  mcpose::tools::AddMissesCommand(app, &status);
  mcpose::tools::AddRelightCommand(app, &status);
  mcpose::tools::AddTwinMarginCommand(app, &status);
  mcpose::tools::AddHwWorkloadCommand(app, &status);
  app.add_subcommand("options-table",
                     "Print the estimator's options table (docs/options.md holds it; a test checks it is current)")
      ->callback([] { std::fputs(mcpose::OptionTableMarkdown().c_str(), stdout); });
  app.add_subcommand("tracker-options-table",
                     "Print the tracker's options table (docs/options.md holds it; a test checks it is current)")
      ->callback([] { std::fputs(mcpose::TrackerOptionTableMarkdown().c_str(), stdout); });
  // Warnings and progress go to stderr; stdout carries only what a command reports.
  spdlog::set_default_logger(spdlog::stderr_color_st("mcpose-tools"));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "mcpose-tools: error: out of memory\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mcpose-tools: error: %s\n", e.what());
    return 1;
  }
  if (!status.ok()) {
    std::fprintf(stderr, "mcpose-tools: error: %s\n", status.ToString().c_str());
    return 1;
  }
  return 0;
}

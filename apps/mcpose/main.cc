#include <cstdio>
#include <exception>
#include <new>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "commands.h"
#include "mcpose/version.h"

int main(int argc, char** argv) {
  CLI::App app{
      "mcpose: 6-DoF object pose estimation by Monte-Carlo sampling on RGB-D frames\n"
      "(YCB-Video native and BOP datasets)."};
  app.require_subcommand(1);
  app.set_version_flag("--version", mcpose::Version());
  mcpose::Status status;
  mcpose::cli::AddEstimateCommand(app, &status);
  mcpose::cli::AddDetectionsFromGtCommand(app, &status);
  mcpose::cli::AddEvalCommand(app, &status);
  mcpose::cli::AddBenchCommand(app, &status);
  mcpose::cli::AddCaptureCommand(app, &status);
  mcpose::cli::AddTrackCommand(app, &status);
  mcpose::cli::AddReportCommand(app, &status);
  mcpose::cli::AddSynthCommand(app, &status);
  // Warnings and progress go to stderr; stdout carries only what a command reports.
  spdlog::set_default_logger(spdlog::stderr_color_st("mcpose"));
  spdlog::set_pattern("[%H:%M:%S] %v");
  // The commands run inside parse. Their errors come back as a Status; what the library cannot
  // turn into one (an allocation that fails, a thread the system refuses) ends here as one line
  // and exit status 1, never as std::terminate. Outputs are written through temporary files and
  // renamed, so none is left half-written.
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "mcpose: error: out of memory (fewer samples, boxes or threads need less)\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mcpose: error: %s\n", e.what());
    return 1;
  }
  if (!status.ok()) {
    std::fprintf(stderr, "mcpose: error: %s\n", status.ToString().c_str());
    return 1;
  }
  return 0;
}

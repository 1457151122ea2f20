#include <cstdio>
#include <filesystem>
#include <fstream>

#include <spdlog/spdlog.h>

#include "commands.h"

namespace mcpose::cli {

Status WriteFileAtomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) return NotFound(path + ": cannot open for writing");
    out << text;
    out.flush();
    if (!out) {
      std::error_code ec;
      std::filesystem::remove(tmp, ec);
      return Internal(path + ": write failed");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) return Internal(path + ": cannot rename temporary file: " + ec.message());
  return Status::Ok();
}

Status CheckWritable(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path p(path);
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return NotFound(path + ": folder " + dir.string() + " does not exist");
  if (fs::is_directory(p, ec)) return InvalidArgument(path + ": is a folder, expected a file path");
  const std::string probe = path + ".probe.tmp";
  {
    std::ofstream out(probe);
    if (!out) return InvalidArgument(path + ": cannot create files in " + dir.string());
  }
  fs::remove(probe, ec);
  return Status::Ok();
}

void AddSimdTargetOption(CLI::App* cmd, std::string* name) {
  cmd->add_option("--simd-target", *name,
                  "Cap the SIMD dispatch at this Highway target (here: " + SimdTargets() +
                      "), e.g. AVX2 on an AVX-512 machine; same results; default: the best");
}

Status ApplySimdTarget(const std::string& name) {
  if (name.empty() || LimitSimdTarget(name)) return Status::Ok();
  return InvalidArgument("--simd-target must be one of: " + SimdTargets() + "; got '" + name + "'");
}

}  // namespace mcpose::cli

int main(int argc, char** argv) {
  CLI::App app{
      "mcpose: 6-DoF object pose estimation by Monte-Carlo sampling on RGB-D frames\n"
      "(YCB-Video native and BOP datasets)."};
  app.require_subcommand(1);
  mcpose::Status status;
  mcpose::cli::AddEstimateCommand(app, &status);
  mcpose::cli::AddDetectionsFromGtCommand(app, &status);
  mcpose::cli::AddEvalCommand(app, &status);
  mcpose::cli::AddBenchCommand(app, &status);
  mcpose::cli::AddAmbiguityCommand(app, &status);
  mcpose::cli::AddTurnProfileCommand(app, &status);
  spdlog::set_pattern("[%H:%M:%S] %v");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  if (!status.ok()) {
    std::fprintf(stderr, "mcpose: error: %s\n", status.ToString().c_str());
    return 1;
  }
  return 0;
}

// Running the command-line programs from integration tests: exit code, stdout and stderr.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace mcpose::testing {

struct CliResult {
  int exit_code = -1;
  std::string out, err;
};

// The whole file as text; empty if it cannot be read.
inline std::string ReadText(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Runs `program args` through the shell, its output captured in files under `dir`.
inline CliResult RunProgram(const std::string& program, const std::string& args, const std::filesystem::path& dir) {
  const std::filesystem::path out = dir / "stdout.txt", err = dir / "stderr.txt";
  const std::string cmd = program + " " + args + " > " + out.string() + " 2> " + err.string();
  const int rc = std::system(cmd.c_str());
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, ReadText(out), ReadText(err)};
}
inline CliResult RunCli(const std::string& args, const std::filesystem::path& dir) {
  return RunProgram(MCPOSE_CLI_PATH, args, dir);
}
inline CliResult RunTools(const std::string& args, const std::filesystem::path& dir) {
  return RunProgram(MCPOSE_TOOLS_PATH, args, dir);
}

}  // namespace mcpose::testing

// Where tests find the real data: $MCPOSE_DATA_DIR, else the folder configured at build time
// (CMake cache variable MCPOSE_DATA_DIR, default ../shared/data beside the source tree).
#pragma once

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

namespace mcpose::testing {

inline std::string DataDir() {
  if (const char* env = std::getenv("MCPOSE_DATA_DIR"); env && *env) return env;
  return MCPOSE_DEFAULT_DATA_DIR;
}
inline std::string YcbvDir() { return DataDir() + "/ycbv"; }
inline std::string BopDir() { return DataDir() + "/bop_ycbv_subset"; }

// The folders TempDir made in this process, removed when it exits.
struct TempDirRegistry {
  std::vector<std::filesystem::path> dirs;
  ~TempDirRegistry() {
    std::error_code ec;
    for (const auto& d : dirs) std::filesystem::remove_all(d, ec);
  }
};
inline TempDirRegistry& TempDirs() {
  static TempDirRegistry registry;
  return registry;
}

// A fresh empty folder under the system temp dir for one test, removed at process exit. The
// process id keeps test processes that ctest runs in parallel (e.g. the instances of a
// parameterized test, which pass the same name) out of each other's folders.
inline std::filesystem::path TempDir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() /
             ("mcpose_test_" + name + "_" + std::to_string(static_cast<long>(::getpid())));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  TempDirs().dirs.push_back(dir);
  return dir;
}

// The names beside `target` that a writer of it makes while it works (`NAME.tmp-XXXXXX`,
// a report's `NAME.old-XXXXXX` and `NAME.lock`): none may be left once a run has ended.
inline std::vector<std::string> LeftBeside(const std::filesystem::path& target) {
  std::vector<std::string> left;
  std::error_code ec;
  const std::filesystem::path dir = target.has_parent_path() ? target.parent_path() : ".";
  const std::string name = target.filename().string();
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    const std::string other = e.path().filename().string();
    if (other.rfind(name + ".tmp", 0) == 0 || other.rfind(name + ".old-", 0) == 0 || other == name + ".lock")
      left.push_back(other);
  }
  return left;
}

}  // namespace mcpose::testing

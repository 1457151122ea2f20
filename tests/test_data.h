// Where tests find the real data: $MCPOSE_DATA_DIR, else the folder configured at build time
// (CMake cache variable MCPOSE_DATA_DIR, default ../shared/data beside the source tree).
#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>

namespace mcpose::testing {

inline std::string DataDir() {
  if (const char* env = std::getenv("MCPOSE_DATA_DIR"); env && *env) return env;
  return MCPOSE_DEFAULT_DATA_DIR;
}
inline std::string YcbvDir() { return DataDir() + "/ycbv"; }
inline std::string BopDir() { return DataDir() + "/bop_ycbv_subset"; }

// A fresh empty folder under the system temp dir for one test.
inline std::filesystem::path TempDir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / ("mcpose_test_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace mcpose::testing

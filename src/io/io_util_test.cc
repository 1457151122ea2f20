#include "mcpose/io_util.h"

#include <filesystem>
#include <fstream>
#include <string>

#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "mcpose/limits.h"
#include "mcpose/json_util.h"
#include "test_data.h"

namespace mcpose::io {
namespace {

namespace fs = std::filesystem;

std::string Read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

mode_t Umask() {
  const mode_t mask = ::umask(0);
  ::umask(mask);
  return mask;
}

mode_t Mode(const fs::path& p) {
  struct stat st {};
  EXPECT_EQ(::lstat(p.c_str(), &st), 0) << p;
  return st.st_mode & 0777;
}

TEST(WriteFileAtomic, WritesTheWholeFileWithTheUsersPermissionsAndLeavesNothingBeside) {
  const fs::path dir = testing::TempDir("write_atomic");
  const fs::path out = dir / "out.txt";
  ASSERT_TRUE(WriteFileAtomic(out.string(), "first").ok());
  ASSERT_TRUE(WriteFileAtomic(out.string(), "second").ok());
  EXPECT_EQ(Read(out), "second");
  EXPECT_EQ(Mode(out), 0666 & ~Umask());
  EXPECT_TRUE(testing::LeftBeside(out).empty());
}

TEST(WriteFileAtomic, ReplacesALinkAtItsNameAndNeverWritesThroughOne) {
  const fs::path dir = testing::TempDir("write_atomic_links");
  std::ofstream(dir / "victim.txt") << "keep";
  // A link at the output's name is replaced; links planted at the names a writer of an earlier
  // version used beside it are not followed.
  fs::create_symlink(dir / "victim.txt", dir / "out.txt");
  fs::create_symlink(dir / "victim.txt", dir / "out.txt.tmp");
  ASSERT_TRUE(WriteFileAtomic((dir / "out.txt").string(), "mine").ok());
  EXPECT_FALSE(fs::is_symlink(dir / "out.txt"));
  EXPECT_EQ(Read(dir / "out.txt"), "mine");
  EXPECT_EQ(Read(dir / "victim.txt"), "keep");
  // A folder at the output's name is refused, and left as it was.
  fs::create_directories(dir / "folder");
  const Status status = WriteFileAtomic((dir / "folder").string(), "x");
  EXPECT_EQ(status.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(status.message().find("is a folder"), std::string::npos) << status.message();
  EXPECT_TRUE(fs::is_empty(dir / "folder"));
}

TEST(CreateBeside, FreshNamesEachTimeWithTheUsersPermissions) {
  const fs::path dir = testing::TempDir("create_beside");
  const std::string target = (dir / "report").string();
  StatusOr<std::string> a = CreateFolderBeside(target, ".tmp-");
  StatusOr<std::string> b = CreateFolderBeside(target, ".tmp-");
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_NE(*a, *b);
  EXPECT_EQ(a->rfind(target + ".tmp-", 0), 0u) << *a;
  EXPECT_EQ(Mode(*a), 0777 & ~Umask());
  StatusOr<TempFile> f = CreateTempFileBeside(target);
  ASSERT_TRUE(f.ok());
  ::close(f->fd);
  EXPECT_EQ(Mode(f->path), 0666 & ~Umask());
  EXPECT_EQ(CreateFolderBeside((dir / "missing" / "x").string(), ".tmp-").status().code(), StatusCode::kNotFound);
}

// A device (or a link to one) never ends: refused, not read until memory runs out.
TEST(ReadFileToString, RefusesDevicesAndLinksToThem) {
  const fs::path dir = testing::TempDir("read_devices");
  fs::create_symlink("/dev/zero", dir / "depth.png");
  for (const std::string& path : {std::string("/dev/zero"), (dir / "depth.png").string()}) {
    const StatusOr<std::string> text = ReadFileToString(path);
    ASSERT_FALSE(text.ok()) << path;
    EXPECT_EQ(text.status().code(), StatusCode::kInvalidArgument);
    EXPECT_NE(text.status().message().find(path + ": not a regular file"), std::string::npos)
        << text.status().message();
  }
}

TEST(ReadJsonFile, RefusesNestingPastTheLimit) {
  const fs::path dir = testing::TempDir("json_deep");
  const int ok_depth = limits::kMaxJsonDepth - 1;
  std::ofstream(dir / "ok.json") << std::string(ok_depth, '[') << std::string(ok_depth, ']');
  EXPECT_TRUE(ReadJsonFile((dir / "ok.json").string()).ok());
  std::ofstream(dir / "deep.json") << std::string(100000, '[') << std::string(100000, ']');
  const StatusOr<nlohmann::json> deep = ReadJsonFile((dir / "deep.json").string());
  ASSERT_FALSE(deep.ok());
  EXPECT_NE(deep.status().message().find("deep.json: JSON nested more than 64 levels deep"), std::string::npos)
      << deep.status().message();
}

}  // namespace
}  // namespace mcpose::io

#include "cli/common.h"

#include <charconv>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "mcpose/limits.h"
#include "mcpose/io_util.h"

namespace mcpose::cli {

void RemoveOutput(const std::string& path) {
  if (path.empty()) return;
  std::error_code ec;
  std::filesystem::remove(path, ec);
}

Status CheckWritable(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path p(path);
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return NotFound(path + ": folder " + dir.string() + " does not exist");
  if (fs::is_directory(p, ec)) return InvalidArgument(path + ": is a folder, expected a file path");
  // The probe is created exclusively under a fresh name: it follows no link and touches no file.
  StatusOr<io::TempFile> probe = io::CreateTempFileBeside(path);
  if (!probe.ok()) return InvalidArgument(path + ": cannot create files in " + dir.string());
  ::close(probe->fd);
  fs::remove(probe->path, ec);
  return Status::Ok();
}

namespace {

// Two paths name the same file: the same after resolving links and "..", or (where both exist)
// the same inode.
bool SameFile(const std::string& a, const std::string& b) {
  namespace fs = std::filesystem;
  std::error_code ec1, ec2;
  const fs::path ca = fs::weakly_canonical(fs::absolute(a), ec1), cb = fs::weakly_canonical(fs::absolute(b), ec2);
  if (!ec1 && !ec2 && ca == cb) return true;
  std::error_code ec;
  return fs::exists(a, ec) && fs::exists(b, ec) && fs::equivalent(a, b, ec) && !ec;
}

}  // namespace

Status CheckOutputsDistinct(std::initializer_list<PathArg> inputs, std::initializer_list<PathArg> outputs) {
  for (auto out = outputs.begin(); out != outputs.end(); ++out) {
    if (out->path.empty()) continue;
    for (const PathArg& in : inputs)
      if (!in.path.empty() && SameFile(out->path, in.path))
        return InvalidArgument(out->path + ": " + out->flag + " names the same file as " + in.flag +
                               ", an input of this run; it would be overwritten");
    for (auto other = outputs.begin(); other != out; ++other)
      if (!other->path.empty() && SameFile(out->path, other->path))
        return InvalidArgument(out->path + ": " + out->flag + " and " + other->flag + " name the same file");
  }
  return Status::Ok();
}

Status CheckOutputsOutsideDataset(const Dataset& dataset, std::initializer_list<PathArg> outputs) {
  namespace fs = std::filesystem;
  const auto canonical = [](const std::string& path) {
    std::error_code ec;
    const fs::path p = fs::weakly_canonical(fs::absolute(path), ec);
    return ec ? fs::absolute(path).lexically_normal() : p;
  };
  // Whether `inner` is `outer` or lies below it (both canonical).
  const auto within = [](const fs::path& inner, const fs::path& outer) {
    const fs::path rel = inner.lexically_relative(outer);
    return !rel.empty() && *rel.begin() != "..";
  };
  for (const PathArg& out : outputs) {
    if (out.path.empty()) continue;
    const fs::path o = canonical(out.path);
    std::error_code ec;
    for (const std::string& folder : {dataset.root(), dataset.models_dir()}) {
      const fs::path f = canonical(folder);
      if (within(f, o))
        return InvalidArgument(out.path + ": " + out.flag + " names a folder holding the dataset " + folder +
                               ", which this run reads");
      if (within(o, f) && fs::exists(fs::symlink_status(out.path, ec)))
        return InvalidArgument(out.path + ": " + out.flag + " names what the dataset folder " + folder +
                               " holds, which this run may read; it would be overwritten (write elsewhere)");
    }
  }
  return Status::Ok();
}

Status KeepScoresAtLeast(double min_score, const std::string& source, std::vector<Detection>* detections) {
  if (!(min_score >= 0 && min_score <= 1)) return InvalidArgument("--min-score must lie in [0, 1]");
  if (min_score == 0) return Status::Ok();
  std::erase_if(*detections, [&](const Detection& d) { return d.score < min_score; });
  if (detections->empty()) return InvalidArgument(source + ": no detection scores at least --min-score " + limits::Num(min_score));
  return Status::Ok();
}


}  // namespace mcpose::cli

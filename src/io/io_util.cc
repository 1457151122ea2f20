#include "mcpose/io_util.h"

#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>
#include <string_view>
#include <system_error>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include "mcpose/limits.h"

namespace mcpose::io {

namespace fs = std::filesystem;

StatusOr<std::string> ReadFileToString(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) return NotFound(path + ": file does not exist");
  if (fs::is_directory(path, ec)) return InvalidArgument(path + ": is a directory, not a file");
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return DataLoss(path + ": cannot open file (" + std::strerror(errno) + ")");
  // A device, a pipe (or a link to one: /dev/zero) never ends; a regular file has its size.
  struct stat st {};
  if (::fstat(::fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) {
    std::fclose(f);
    return InvalidArgument(path + ": not a regular file (a device, pipe or socket is not read)");
  }
  if (st.st_size > limits::kMaxFileBytes) {
    std::fclose(f);
    return InvalidArgument(path + ": " + std::to_string(st.st_size) + " bytes, more than the limit of " +
                           std::to_string(limits::kMaxFileBytes) + " for an input file");
  }
  std::string contents;
  contents.reserve(static_cast<size_t>(st.st_size));
  char buffer[1 << 16];
  size_t n = 0;
  while (contents.size() <= static_cast<size_t>(limits::kMaxFileBytes) &&
         (n = std::fread(buffer, 1, sizeof(buffer), f)) > 0)
    contents.append(buffer, n);
  const bool failed = std::ferror(f) != 0;
  std::fclose(f);
  if (failed) return DataLoss(path + ": read error");
  if (contents.size() > static_cast<size_t>(limits::kMaxFileBytes))
    return InvalidArgument(path + ": grew past the limit of " + std::to_string(limits::kMaxFileBytes) +
                           " bytes while being read");
  return contents;
}

namespace {

// `path` + `tag` + six random letters: a name to try for a new file or folder beside `path`.
std::string FreshName(const std::string& path, const char* tag, std::random_device& entropy) {
  static constexpr char kLetters[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
  std::string name = path + tag;
  for (int i = 0; i < 6; ++i) name += kLetters[entropy() % (sizeof kLetters - 1)];
  return name;
}

}  // namespace

StatusOr<TempFile> CreateTempFileBeside(const std::string& path) {
  // Created exclusively (O_CREAT | O_EXCL, which never follows a link) under a fresh name, with
  // the permissions the user's umask gives any new file.
  std::random_device entropy;
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::string name = FreshName(path, ".tmp-", entropy);
    const int fd = ::open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd >= 0) return TempFile{fd, name};
    if (errno != EEXIST)
      return NotFound(path + ": cannot create a temporary file beside it (" + std::strerror(errno) + ")");
  }
  return Internal(path + ": cannot find a free temporary name beside it");
}

StatusOr<std::string> CreateFolderBeside(const std::string& path, const char* tag) {
  std::random_device entropy;
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::string name = FreshName(path, tag, entropy);
    if (::mkdir(name.c_str(), 0777) == 0) return name;
    if (errno != EEXIST)
      return NotFound(path + ": cannot create a folder beside it (" + std::strerror(errno) + ")");
  }
  return Internal(path + ": cannot find a free folder name beside it");
}

namespace {
// What a lock file holds: a file of that name holding anything else is the user's, never taken.
constexpr std::string_view kLockText = "mcpose lock\n";
}  // namespace

StatusOr<std::unique_ptr<FileLock>> FileLock::Acquire(const std::string& path) {
  // A holder removes the file when it is done: a process that opened the old file and locks it
  // afterwards finds the name gone or another file's, and opens the name again.
  for (int attempt = 0; attempt < 100; ++attempt) {
    bool created = true;
    int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd < 0 && errno == EEXIST) {
      created = false;
      fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK);
      if (fd < 0 && errno == ENOENT) continue;  // removed in between
    }
    if (fd < 0 && errno == ELOOP) return InvalidArgument(path + ": is a link; a lock file is never one");
    if (fd < 0) return NotFound(path + ": cannot create the lock file (" + std::strerror(errno) + ")");
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int error = errno;
      ::close(fd);
      if (error == EWOULDBLOCK) return InvalidArgument(path + ": held by another run writing the same output");
      return Internal(path + ": cannot lock (" + std::strerror(error) + ")");
    }
    struct stat held, named;
    if (::fstat(fd, &held) != 0 || ::lstat(path.c_str(), &named) != 0 || held.st_dev != named.st_dev ||
        held.st_ino != named.st_ino) {
      ::close(fd);
      continue;
    }
    // A file this run did not create is taken over only if it is a lock file a killed run left.
    std::string text(kLockText.size() + 1, '\0');
    const ssize_t got = created ? 0 : ::pread(fd, text.data(), text.size(), 0);
    if (!S_ISREG(held.st_mode) || (!created && std::string_view(text.data(), got > 0 ? got : 0) != kLockText)) {
      ::close(fd);
      return InvalidArgument(path + ": exists and is not a lock file of mcpose; it is left alone (move it away)");
    }
    if (created && ::write(fd, kLockText.data(), kLockText.size()) != static_cast<ssize_t>(kLockText.size())) {
      ::unlink(path.c_str());
      ::close(fd);
      return Internal(path + ": cannot write the lock file (" + std::strerror(errno) + ")");
    }
    return std::unique_ptr<FileLock>(new FileLock(path, fd));
  }
  return Internal(path + ": cannot take the lock (the file keeps changing)");
}

FileLock::~FileLock() {
  ::unlink(path_.c_str());
  ::close(fd_);
}

Status WriteFileAtomic(const std::string& path, const std::string& contents) {
  std::error_code ec;
  if (fs::is_directory(fs::symlink_status(path, ec))) return InvalidArgument(path + ": is a folder, expected a file path");
  MCPOSE_ASSIGN_OR_RETURN(TempFile tmp, CreateTempFileBeside(path));
  bool wrote = true;
  for (size_t done = 0; wrote && done < contents.size();) {
    const ssize_t n = ::write(tmp.fd, contents.data() + done, contents.size() - done);
    if (n < 0 && errno == EINTR) continue;
    wrote = n > 0;
    if (wrote) done += static_cast<size_t>(n);
  }
  // The data reach the disk before the rename makes them the file: after a power loss the name
  // holds the old file or the whole new one.
  const bool synced = wrote && ::fsync(tmp.fd) == 0;
  const bool closed = ::close(tmp.fd) == 0;
  if (!wrote || !synced || !closed) {
    fs::remove(tmp.path, ec);
    return Internal(tmp.path + ": write failed (disk full?)");
  }
  // rename replaces a link at `path` itself, never the file it points to.
  fs::rename(tmp.path, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp.path, ignored);
    return Internal(path + ": cannot rename " + tmp.path + " to it (" + ec.message() + ")");
  }
  return SyncParentDirectory(path);
}

Status SyncParentDirectory(const std::string& path) {
  fs::path dir = fs::path(path).parent_path();
  if (dir.empty()) dir = ".";
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return Internal(dir.string() + ": cannot open folder to flush it (" + std::strerror(errno) + ")");
  const bool synced = ::fsync(fd) == 0;
  const int error = errno;
  ::close(fd);
  if (!synced) return Internal(dir.string() + ": cannot flush folder to disk (" + std::strerror(error) + ")");
  return Status::Ok();
}

bool ParseDouble(std::string_view token, double* value) {
  if (token.empty()) return false;
  const char* first = token.data();
  const char* last = token.data() + token.size();
  if (*first == '+') ++first;  // from_chars rejects a leading '+', which printf-style writers use
  const auto [ptr, ec] = std::from_chars(first, last, *value);
  return ec == std::errc() && ptr == last;
}

bool ParseInt(std::string_view token, int* value) {
  if (token.empty()) return false;
  const char* first = token.data();
  const char* last = token.data() + token.size();
  if (*first == '+') ++first;
  const auto [ptr, ec] = std::from_chars(first, last, *value);
  return ec == std::errc() && ptr == last;
}

std::string_view Trim(std::string_view text) {
  constexpr std::string_view kSpace = " \t\r\n";
  const size_t begin = text.find_first_not_of(kSpace);
  if (begin == std::string_view::npos) return {};
  const size_t end = text.find_last_not_of(kSpace);
  return text.substr(begin, end - begin + 1);
}

std::vector<std::string_view> SplitWhitespace(std::string_view text) {
  std::vector<std::string_view> tokens;
  size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && (text[i] == ' ' || text[i] == '\t' || text[i] == '\r')) ++i;
    const size_t begin = i;
    while (i < text.size() && text[i] != ' ' && text[i] != '\t' && text[i] != '\r') ++i;
    if (i > begin) tokens.push_back(text.substr(begin, i - begin));
  }
  return tokens;
}

std::vector<std::string_view> Split(std::string_view text, char sep) {
  std::vector<std::string_view> fields;
  size_t begin = 0;
  while (true) {
    const size_t end = text.find(sep, begin);
    if (end == std::string_view::npos) {
      fields.push_back(text.substr(begin));
      return fields;
    }
    fields.push_back(text.substr(begin, end - begin));
    begin = end + 1;
  }
}

std::vector<std::string_view> SplitLines(std::string_view text) {
  std::vector<std::string_view> lines;
  size_t begin = 0;
  while (begin < text.size()) {
    size_t end = text.find('\n', begin);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(begin, end - begin);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.push_back(line);
    begin = end + 1;
  }
  return lines;
}

Status CheckMeshCoordinates(const std::string& path, const Mesh& mesh) {
  for (size_t i = 0; i < mesh.vertices_m.size(); ++i) {
    if (const std::string problem = limits::CheckCoordinates(mesh.vertices_m[i]); !problem.empty())
      return InvalidArgument(path + ": vertex " + std::to_string(i + 1) + ": " + problem);
  }
  return Status::Ok();
}

std::string FileName(const std::string& path) { return fs::path(path).filename().string(); }

}  // namespace mcpose::io

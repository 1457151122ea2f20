// Small helpers shared by the file readers and writers of src/io: whole-file reads, atomic
// writes, strict number parsing and whitespace splitting. All report errors through Status.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "mcpose/mesh.h"
#include "mcpose/status.h"

namespace mcpose::io {

// The bytes of `path`. NotFound if it does not exist, DataLoss if it cannot be read.
StatusOr<std::string> ReadFileToString(const std::string& path);

// A new file beside `path`, named `path` + ".tmp-" and six random characters, created
// exclusively: never a link someone planted, never a file that existed. The caller closes `fd`.
struct TempFile {
  int fd = -1;
  std::string path;
};
StatusOr<TempFile> CreateTempFileBeside(const std::string& path);

// A new, empty folder beside `path`, named `path` + `tag` + six random characters (e.g. tag
// ".tmp-"), created exclusively with the permissions the user's umask gives. Its name.
StatusOr<std::string> CreateFolderBeside(const std::string& path, const char* tag);

// An exclusive lock held through the file `path` (created exclusively, never through a link) for
// as long as the object lives; the file is removed when it goes. A lock file left by a run that
// was killed holds no lock (the system drops it) and is taken over; a file of that name holding
// anything but a lock file's text is the user's and refused, never removed.
class FileLock {
 public:
  // Fails at once, naming `path`, if another process holds it.
  static StatusOr<std::unique_ptr<FileLock>> Acquire(const std::string& path);
  ~FileLock();
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  FileLock(std::string path, int fd) : path_(std::move(path)), fd_(fd) {}
  std::string path_;
  int fd_ = -1;
};

// Writes `contents` to a new temporary file beside `path` (CreateTempFileBeside), flushes it to
// disk, then renames it to `path`: readers never see a partial file, on error no file is left
// behind, and a link at `path` or beside it is replaced, never written through. Every output
// file of the library and the command-line tools goes through here.
Status WriteFileAtomic(const std::string& path, const std::string& contents);

// Flushes the folder holding `path` to disk, so that a rename or removal of `path` in it
// survives a power loss.
Status SyncParentDirectory(const std::string& path);

// Strict parsers: the whole token must be a number (no leading/trailing characters).
bool ParseDouble(std::string_view token, double* value);
bool ParseInt(std::string_view token, int* value);

// `text` without leading and trailing whitespace (space, tab, CR, LF).
std::string_view Trim(std::string_view text);
// Tokens of `text` separated by runs of spaces or tabs.
std::vector<std::string_view> SplitWhitespace(std::string_view text);
// Fields of `text` separated by `sep` (empty fields kept).
std::vector<std::string_view> Split(std::string_view text, char sep);
// The lines of `text` (LF or CRLF endings; the CR is removed).
std::vector<std::string_view> SplitLines(std::string_view text);

// Ok if every vertex of `mesh` is finite and under limits::kMaxCoordinateM in each coordinate;
// else an error naming `path`, the vertex and the coordinate.
Status CheckMeshCoordinates(const std::string& path, const Mesh& mesh);

// The last path component, for short error messages ("scene_gt.json").
std::string FileName(const std::string& path);

}  // namespace mcpose::io

#include "mcpose/results_journal.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <set>
#include <tuple>

#include "mcpose/io_util.h"
#include "mcpose/options_json.h"
#include "io/results_csv.h"
#include "mcpose/version.h"

namespace mcpose::io {

namespace {

constexpr std::string_view kMagic = "# mcpose results journal ";
constexpr std::string_view kDone = "# done ";

uint64_t Fnv1a(std::string_view text, uint64_t h = 1469598103934665603ull) {
  for (const unsigned char c : text) h = (h ^ c) * 1099511628211ull;
  return h;
}

Status WriteAll(int fd, const std::string& path, const std::string& text) {
  size_t written = 0;
  while (written < text.size()) {
    const ssize_t n = ::write(fd, text.data() + written, text.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return Internal(path + ": write failed (" + std::strerror(errno) + ")");
    written += static_cast<size_t>(n);
  }
  if (::fsync(fd) != 0) return Internal(path + ": cannot flush to disk (" + std::strerror(errno) + ")");
  return Status::Ok();
}

// Whether a line from `pos` on in `text` is an end mark.
bool HasEndMarkFrom(const std::string& text, size_t pos) {
  for (size_t at = pos; at < text.size();) {
    if (std::string_view(text).substr(at, kDone.size()) == kDone) return true;
    const size_t end = text.find('\n', at);
    if (end == std::string::npos) return false;
    at = end + 1;
  }
  return false;
}

// The finished images of a journal's text and the length of its text up to the last end mark.
Status ParseJournal(const std::string& path, const std::string& text, const std::string& fingerprint,
                    std::map<FrameKey, std::vector<PoseResult>>* images, size_t* kept_bytes) {
  *kept_bytes = 0;
  size_t pos = 0;
  int line_no = 0;
  std::vector<PoseResult> pending;
  while (pos < text.size()) {
    const size_t end = text.find('\n', pos);
    if (end == std::string::npos) break;  // a line cut short by the kill: dropped
    const std::string_view line(text.data() + pos, end - pos);
    pos = end + 1;
    ++line_no;
    const std::string where = path + ": line " + std::to_string(line_no) + ": ";
    if (line_no == 1) {
      if (line.substr(0, kMagic.size()) != kMagic) return InvalidArgument(where + "not a mcpose results journal");
      if (line.substr(kMagic.size()) != fingerprint)
        return InvalidArgument(path + ": was written by a run with other options, detections, dataset or "
                               "mcpose version; rerun without --resume to start afresh");
      *kept_bytes = pos;
      continue;
    }
    if (line.substr(0, kDone.size()) == kDone) {
      const std::vector<std::string_view> f = SplitWhitespace(line.substr(kDone.size()));
      FrameKey key;
      int rows = 0;
      if (f.size() != 3 || !ParseInt(f[0], &key.scene_id) || !ParseInt(f[1], &key.image_id) ||
          !ParseInt(f[2], &rows))
        return InvalidArgument(where + "expected '# done <scene_id> <im_id> <rows>'");
      if (rows != static_cast<int>(pending.size()) ||
          std::any_of(pending.begin(), pending.end(), [&](const PoseResult& r) {
            return r.scene_id != key.scene_id || r.im_id != key.image_id;
          }))
        return InvalidArgument(where + "the rows before this end mark are not the " + std::to_string(rows) +
                               " rows of scene_id " + std::to_string(key.scene_id) + ", im_id " +
                               std::to_string(key.image_id));
      (*images)[key] = std::move(pending);
      pending.clear();
      *kept_bytes = pos;
      continue;
    }
    PoseResult r;
    const std::string problem = ParseResultsCsvRow(line, &r);
    if (!problem.empty()) {
      // A torn write (a power loss can leave zeros or a stale block after the last flushed
      // image) is dropped like a line cut short; a bad line with a finished image after it is not.
      if (!HasEndMarkFrom(text, pos)) break;
      return InvalidArgument(where + problem);
    }
    pending.push_back(r);
  }
  return Status::Ok();
}

}  // namespace

std::string RunFingerprint(const EstimatorOptions& options, const std::vector<Detection>& detections,
                           const RunSource& source) {
  EstimatorOptions o = options;
  o.engine.threads = 0;
  o.engine.simd_target = SimdTarget::kBest;
  uint64_t h = Fnv1a(OptionsToJson(o).dump());
  const auto absolute = [](const std::string& path) {
    std::error_code ec;
    const std::filesystem::path p = std::filesystem::weakly_canonical(std::filesystem::absolute(path, ec), ec);
    return ec ? path : p.string();
  };
  // Each field ends with a byte no path holds, so that no two sources hash the same text.
  for (const std::string& field : {std::string(Version()), absolute(source.dataset_root), source.split,
                                   absolute(source.models_dir), source.instance_counts})
    h = Fnv1a(std::string_view(field.c_str(), field.size() + 1), h);
  for (const Detection& d : detections) {
    char text[256];
    std::snprintf(text, sizeof text, "%d %d %d %.17g %.17g %.17g %.17g %.17g\n", d.scene_id, d.image_id, d.obj_id,
                  d.score, d.x, d.y, d.w, d.h);
    h = Fnv1a(text, h);
  }
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  return hex;
}

std::string JournalPath(const std::string& out) { return out + ".partial"; }

StatusOr<std::unique_ptr<ResultsJournal>> ResultsJournal::Open(const std::string& out,
                                                               const std::string& fingerprint, bool resume) {
  const std::string path = JournalPath(out);
  // O_NOFOLLOW: a link planted at the journal's name is refused, never written through.
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
  if (fd < 0 && errno == ELOOP) return InvalidArgument(path + ": is a link; the journal is never written through one");
  if (fd < 0) return NotFound(path + ": cannot create file (" + std::strerror(errno) + ")");
  struct stat st;
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    return InvalidArgument(path + ": is not a regular file");
  }
  std::unique_ptr<ResultsJournal> journal(new ResultsJournal(out, fd));
  // Two runs appending to one journal would interleave their images: the second one stops here.
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    if (error == EWOULDBLOCK)
      return InvalidArgument(path + ": in use by another run writing " + out + " (wait for it or stop it)");
    return Internal(path + ": cannot lock (" + std::strerror(error) + ")");
  }
  std::map<FrameKey, std::vector<PoseResult>> images;
  size_t kept_bytes = 0;
  if (resume) {
    MCPOSE_ASSIGN_OR_RETURN(std::string text, ReadFileToString(path));
    MCPOSE_RETURN_IF_ERROR(ParseJournal(path, text, fingerprint, &images, &kept_bytes));
  }
  // Whatever follows the last finished image (or the whole file, on a fresh start) goes.
  if (::ftruncate(fd, static_cast<off_t>(kept_bytes)) != 0 ||
      ::lseek(fd, static_cast<off_t>(kept_bytes), SEEK_SET) < 0)
    return Internal(path + ": cannot truncate (" + std::strerror(errno) + ")");
  if (kept_bytes == 0) {
    MCPOSE_RETURN_IF_ERROR(WriteAll(fd, path, std::string(kMagic) + fingerprint + "\n"));
    MCPOSE_RETURN_IF_ERROR(SyncParentDirectory(path));
  }
  journal->kept_images_ = static_cast<int>(images.size());
  journal->images_ = std::move(images);
  return journal;
}

Status ResultsJournal::CheckKeptAgainst(const std::vector<Detection>& detections) const {
  std::map<FrameKey, std::map<int, int>> detected;  // boxes of each class in each image
  for (const Detection& d : detections) ++detected[FrameKey{d.scene_id, d.image_id}][d.obj_id];
  const std::string path = JournalPath(out_);
  for (const auto& [key, rows] : images_) {
    const std::string block = path + ": the rows of scene_id " + std::to_string(key.scene_id) + ", im_id " +
                              std::to_string(key.image_id);
    const auto image = detected.find(key);
    if (image == detected.end()) return InvalidArgument(block + ": no detection names this image");
    std::map<int, int> seen;
    for (const PoseResult& r : rows) {
      if (r.scene_id != key.scene_id || r.im_id != key.image_id)
        return InvalidArgument(block + ": a row of scene_id " + std::to_string(r.scene_id) + ", im_id " +
                               std::to_string(r.im_id) + " among them");
      if (!image->second.contains(r.obj_id))
        return InvalidArgument(block + ": a row of obj_id " + std::to_string(r.obj_id) +
                               ", which no detection of this image names");
      if (++seen[r.obj_id] > image->second.at(r.obj_id))  // an instance per box at most
        return InvalidArgument(block + ": more rows of obj_id " + std::to_string(r.obj_id) + " than its " +
                               std::to_string(image->second.at(r.obj_id)) + " box(es) in this image");
    }
  }
  return Status::Ok();
}

ResultsJournal::~ResultsJournal() {
  if (fd_ >= 0) ::close(fd_);
}

Status ResultsJournal::Append(const FrameKey& key, const std::vector<PoseResult>& rows) {
  std::string text;
  for (const PoseResult& r : rows) text += ResultsCsvRow(r) + "\n";
  text += std::string(kDone) + std::to_string(key.scene_id) + " " + std::to_string(key.image_id) + " " +
          std::to_string(rows.size()) + "\n";
  MCPOSE_RETURN_IF_ERROR(WriteAll(fd_, JournalPath(out_), text));
  images_[key] = rows;
  return Status::Ok();
}

Status ResultsJournal::Finish() {
  std::vector<PoseResult> all;
  for (const auto& [key, rows] : images_) all.insert(all.end(), rows.begin(), rows.end());
  std::stable_sort(all.begin(), all.end(), [](const PoseResult& a, const PoseResult& b) {
    return std::tie(a.scene_id, a.im_id, a.obj_id) < std::tie(b.scene_id, b.im_id, b.obj_id);
  });
  MCPOSE_RETURN_IF_ERROR(WriteResultsCsv(out_, all));
  // Removed while still locked, so that no other run opens it in between.
  std::error_code ec;
  std::filesystem::remove(JournalPath(out_), ec);
  ::close(fd_);
  fd_ = -1;
  if (ec) return Internal(JournalPath(out_) + ": cannot remove (" + ec.message() + ")");
  return SyncParentDirectory(JournalPath(out_));
}

}  // namespace mcpose::io

// The results journal of a run, OUT.partial beside the results CSV OUT: the rows of each
// finished image are appended and flushed to disk before the next image starts, so a run
// killed at any point (SIGINT, SIGKILL, power loss) loses at most the image it was on, and a
// rerun with --resume redoes only the images the journal lacks. The CSV itself is written once,
// at the end, through a temporary file and a rename.
//
// Format, one line each:
//   # mcpose results journal <fingerprint>
//   <results CSV row>                         the rows of one image, then
//   # done <scene_id> <im_id> <rows>          that image's end mark
// Rows after the last end mark (an image cut short) are dropped on resume.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "mcpose/dataset.h"
#include "mcpose/detection.h"
#include "mcpose/options.h"
#include "mcpose/results.h"
#include "mcpose/status.h"

namespace mcpose::io {

// What decides a run's rows: the options except the thread count and SIMD target (which
// change no result), and the detections. A journal is resumed only under the same fingerprint.
std::string RunFingerprint(const EstimatorOptions& options, const std::vector<Detection>& detections);

// The journal path of results CSV `out`.
std::string JournalPath(const std::string& out);

class ResultsJournal {
 public:
  // Opens the journal of results CSV `out`. Without `resume` a new journal replaces any old
  // one. With `resume` the finished images of an existing journal of the same fingerprint are
  // kept (a trailing unfinished image is cut off); no journal is a fresh start. Errors name
  // the journal: another fingerprint, a malformed line.
  static StatusOr<std::unique_ptr<ResultsJournal>> Open(const std::string& out, const std::string& fingerprint,
                                                        bool resume);
  ~ResultsJournal();

  // The images whose rows the journal holds (kept from earlier runs and appended since).
  const std::map<FrameKey, std::vector<PoseResult>>& images() const { return images_; }
  bool Has(const FrameKey& key) const { return images_.count(key) > 0; }
  int kept_images() const { return kept_images_; }

  // Appends one finished image's rows and its end mark, and flushes them to disk.
  Status Append(const FrameKey& key, const std::vector<PoseResult>& rows);
  // Writes every row, sorted by (scene_id, im_id, obj_id), to `out` atomically, then removes
  // the journal.
  Status Finish();

 private:
  ResultsJournal(std::string out, int fd) : out_(std::move(out)), fd_(fd) {}
  std::string out_;
  int fd_ = -1;
  int kept_images_ = 0;
  std::map<FrameKey, std::vector<PoseResult>> images_;
};

}  // namespace mcpose::io

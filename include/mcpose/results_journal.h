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
// Rows after the last end mark (an image cut short, or a torn write after a power loss) are
// dropped on resume. One run at a time holds a journal: it is locked (flock) while open.
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

// Where a run reads its frames and meshes: the dataset root, the split, the models folder in
// use (Dataset::models_dir()).
struct RunSource {
  std::string dataset_root, split, models_dir;
  std::string instance_counts;  // the inst_count of each target ("scene im obj n" lines), or empty
};

// What decides a run's rows: the options except the thread count (which changes no result;
// the SIMD target is not an option), the detections, the dataset, split and models folder (as
// absolute paths, so that the same folder named two ways is one), the instance counts
// and the library's version. A journal is resumed only under the same fingerprint.
std::string RunFingerprint(const EstimatorOptions& options, const std::vector<Detection>& detections,
                           const RunSource& source);

// The journal path of results CSV `out`.
std::string JournalPath(const std::string& out);

class ResultsJournal {
 public:
  // Opens and locks the journal of results CSV `out`. Without `resume` a new journal replaces
  // any old one. With `resume` the finished images of an existing journal of the same
  // fingerprint are kept (whatever follows the last end mark is cut off); no journal is a fresh
  // start. Errors name the journal: held by another run, another fingerprint, a malformed line
  // before the last end mark.
  static StatusOr<std::unique_ptr<ResultsJournal>> Open(const std::string& out, const std::string& fingerprint,
                                                        bool resume);
  ~ResultsJournal();

  // The images whose rows the journal holds (kept from earlier runs and appended since).
  const std::map<FrameKey, std::vector<PoseResult>>& images() const { return images_; }
  bool Has(const FrameKey& key) const { return images_.count(key) > 0; }
  int kept_images() const { return kept_images_; }
  // Every kept image is one the detections name, and each of its rows is of a class they name
  // in that image, with no more rows than the class has boxes there (an instance per box at
  // most): a journal edited by hand, or one of another detections file
  // under the same fingerprint, is refused with one line naming the journal.
  Status CheckKeptAgainst(const std::vector<Detection>& detections) const;

  // Appends one finished image's rows and its end mark, and flushes them to disk.
  Status Append(const FrameKey& key, const std::vector<PoseResult>& rows);
  // Writes every row, sorted by (scene_id, im_id, obj_id), to `out` atomically, then removes
  // the journal (and the removal reaches the disk before this returns).
  Status Finish();

 private:
  ResultsJournal(std::string out, int fd) : out_(std::move(out)), fd_(fd) {}
  std::string out_;
  int fd_ = -1;
  int kept_images_ = 0;
  std::map<FrameKey, std::vector<PoseResult>> images_;
};

}  // namespace mcpose::io

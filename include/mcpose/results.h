// Pose results in the BOP results CSV format:
//   scene_id,im_id,obj_id,score,R,t,time
// R: 9 numbers row-major separated by spaces; t: 3 numbers in millimetres; time: seconds.
#pragma once

#include <string>
#include <vector>

#include "mcpose/se3.h"
#include "mcpose/status.h"

namespace mcpose {

struct PoseResult {
  int scene_id = 0;
  int im_id = 0;
  int obj_id = 0;
  double score = 0;
  SE3 T_cam_obj;      // translation in metres in memory; millimetres in the file
  double time_s = -1;  // seconds spent on the whole image; -1 is written as -1
};

// Writes to a new file beside `path` (`path.tmp-XXXXXX`, created exclusively), flushed to disk,
// then renamed to `path`: a failed or killed run leaves no partial file, and a link at `path` is
// replaced, never written through.
Status WriteResultsCsv(const std::string& path, const std::vector<PoseResult>& results);
StatusOr<std::vector<PoseResult>> ReadResultsCsv(const std::string& path);

}  // namespace mcpose

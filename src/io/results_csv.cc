// BOP results CSV: scene_id,im_id,obj_id,score,R,t,time with R row-major and t in millimetres.
#include "mcpose/results.h"

#include <cmath>
#include <cstdio>
#include <exception>

#include "mcpose/limits.h"
#include "mcpose/io_util.h"
#include "io/results_csv.h"

namespace mcpose {
namespace {

constexpr const char* kHeader = "scene_id,im_id,obj_id,score,R,t,time";
constexpr double kMmPerMetre = 1000.0;

void AppendF(std::string* out, const char* format, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), format, value);
  *out += buffer;
}

// Parses `field` as exactly `n` space-separated finite numbers.
bool ParseNumbers(std::string_view field, size_t n, double* out) {
  const std::vector<std::string_view> tokens = io::SplitWhitespace(field);
  if (tokens.size() != n) return false;
  for (size_t i = 0; i < n; ++i) {
    if (!io::ParseDouble(tokens[i], &out[i]) || !std::isfinite(out[i])) return false;
  }
  return true;
}

// Empty on success, else the problem with the line.
std::string ParseLine(std::string_view line, PoseResult* r) {
  const std::vector<std::string_view> fields = io::Split(line, ',');
  if (fields.size() != 7) {
    return "expected 7 comma-separated fields, got " + std::to_string(fields.size());
  }
  if (!io::ParseInt(io::Trim(fields[0]), &r->scene_id)) return "scene_id is not an integer";
  if (!io::ParseInt(io::Trim(fields[1]), &r->im_id)) return "im_id is not an integer";
  if (!io::ParseInt(io::Trim(fields[2]), &r->obj_id)) return "obj_id is not an integer";
  if (r->scene_id < 0 || r->im_id < 0) return "scene_id and im_id must be >= 0";
  if (r->obj_id < 1) return "obj_id must be a positive integer";
  if (!io::ParseDouble(io::Trim(fields[3]), &r->score) || !std::isfinite(r->score)) {
    return "score is not a finite number";
  }
  double R[9], t_mm[3];
  if (!ParseNumbers(fields[4], 9, R)) return "R must be 9 space-separated finite numbers";
  if (!ParseNumbers(fields[5], 3, t_mm)) return "t must be 3 space-separated finite numbers";
  if (!io::ParseDouble(io::Trim(fields[6]), &r->time_s) || !std::isfinite(r->time_s)) {
    return "time is not a finite number";
  }
  if (r->time_s < 0) r->time_s = -1;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) r->T_cam_obj.R(i, j) = R[3 * i + j];
    r->T_cam_obj.t(i) = t_mm[i] / kMmPerMetre;
  }
  // A rotation: orthonormal with determinant +1, to the precision a text file carries.
  if (std::string problem = limits::CheckRotation(r->T_cam_obj.R); !problem.empty()) return problem;
  if (std::string problem = limits::CheckCoordinates(r->T_cam_obj.t); !problem.empty()) return "t: " + problem;
  return {};
}

}  // namespace

namespace io {

std::string ResultsCsvRow(const PoseResult& r) {
  std::string text;
  text += std::to_string(r.scene_id) + "," + std::to_string(r.im_id) + "," +
          std::to_string(r.obj_id) + ",";
  AppendF(&text, "%.9g", r.score);
  text += ",";
  for (int k = 0; k < 9; ++k) {
    if (k) text += " ";
    AppendF(&text, "%.9g", r.T_cam_obj.R(k / 3, k % 3));
  }
  text += ",";
  for (int k = 0; k < 3; ++k) {
    if (k) text += " ";
    AppendF(&text, "%.6f", r.T_cam_obj.t(k) * kMmPerMetre);
  }
  text += ",";
  if (r.time_s < 0) {
    text += "-1";
  } else {
    AppendF(&text, "%.6f", r.time_s);
  }
  return text;
}

std::string ParseResultsCsvRow(std::string_view line, PoseResult* r) { return ParseLine(line, r); }

std::string_view ResultsCsvHeader() { return kHeader; }

}  // namespace io

Status WriteResultsCsv(const std::string& path, const std::vector<PoseResult>& results) {
  try {
    std::string text = std::string(kHeader) + "\n";
    for (size_t i = 0; i < results.size(); ++i) {
      const PoseResult& r = results[i];
      if (!std::isfinite(r.score) || !r.T_cam_obj.R.allFinite() || !r.T_cam_obj.t.allFinite() ||
          !std::isfinite(r.time_s)) {
        return InvalidArgument(path + ": result " + std::to_string(i) +
                               " has a non-finite score, pose or time");
      }
      text += io::ResultsCsvRow(r) + "\n";
    }
    return io::WriteFileAtomic(path, text);
  } catch (const std::exception& e) {
    return Internal(path + ": cannot write results (" + e.what() + ")");
  }
}

StatusOr<std::vector<PoseResult>> ReadResultsCsv(const std::string& path) {
  try {
    MCPOSE_ASSIGN_OR_RETURN(std::string text, io::ReadFileToString(path));
    const std::vector<std::string_view> lines = io::SplitLines(text);
    if (lines.empty() || io::Trim(lines[0]) != kHeader) {
      return InvalidArgument(path + ": line 1: expected the header '" + std::string(kHeader) + "'");
    }
    std::vector<PoseResult> results;
    for (size_t i = 1; i < lines.size(); ++i) {
      if (io::Trim(lines[i]).empty()) continue;
      PoseResult r;
      const std::string problem = ParseLine(lines[i], &r);
      if (!problem.empty()) {
        return InvalidArgument(path + ": line " + std::to_string(i + 1) + ": " + problem);
      }
      results.push_back(r);
    }
    return results;
  } catch (const std::exception& e) {
    return Internal(path + ": cannot read results (" + e.what() + ")");
  }
}

}  // namespace mcpose

// BOP detections JSON: [{"scene_id", "image_id", "category_id", "score", "bbox": [x, y, w, h],
// "time" (optional)}, ...].
#include "mcpose/detection.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>

#include "mcpose/limits.h"
#include "mcpose/io_util.h"
#include "mcpose/json_util.h"

namespace mcpose {
namespace {

using nlohmann::json;

std::string Number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

// Parses one entry; empty string on success, else the problem.
std::string ParseEntry(const json& entry, Detection* d) {
  if (!entry.is_object()) return "expected an object";
  struct IntKey {
    const char* name;
    int* value;
  } int_keys[] = {{"scene_id", &d->scene_id}, {"image_id", &d->image_id},
                  {"category_id", &d->obj_id}};
  for (const IntKey& key : int_keys) {
    if (!entry.contains(key.name)) return std::string("missing key '") + key.name + "'";
    if (!io::JsonToInt(entry[key.name], key.value)) {
      return std::string("'") + key.name + "' must be an integer";
    }
  }
  if (!entry.contains("score")) return "missing key 'score'";
  if (!io::JsonToDouble(entry["score"], &d->score)) return "score must be a finite number";
  if (!entry.contains("bbox")) return "missing key 'bbox'";
  double box[4];
  if (!io::JsonToDoubles(entry["bbox"], 4, box)) return "bbox must have 4 numbers";
  d->x = box[0];
  d->y = box[1];
  d->w = box[2];
  d->h = box[3];
  d->time_s = -1;
  if (entry.contains("time") && !entry["time"].is_null()) {
    if (!io::JsonToDouble(entry["time"], &d->time_s)) return "time must be a finite number";
    if (d->time_s < 0) d->time_s = -1;
  }
  return CheckDetection(*d);
}

}  // namespace

double BoxIou(const Detection& a, const Detection& b) {
  const double ix = std::max(0.0, std::min(a.x + a.w, b.x + b.w) - std::max(a.x, b.x));
  const double iy = std::max(0.0, std::min(a.y + a.h, b.y + b.h) - std::max(a.y, b.y));
  const double inter = ix * iy;
  const double uni = a.w * a.h + b.w * b.h - inter;
  return uni > 0 ? inter / uni : 0.0;
}

std::string CheckDetectionBox(const Detection& d) {
  if (!std::isfinite(d.score) || d.score < 0 || d.score > 1) {
    return "score must be a finite number in [0, 1], got " + Number(d.score);
  }
  if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.w) || !std::isfinite(d.h)) {
    return "bbox must have 4 finite numbers";
  }
  if (!(d.w > 0) || !(d.h > 0)) {
    return "bbox width and height must be positive, got " + BoxText(d);
  }
  for (double v : {d.x, d.y, d.w, d.h}) {
    if (std::abs(v) > limits::kMaxBoxPx)
      return "bbox " + BoxText(d) + " has a value outside +-" + Number(limits::kMaxBoxPx) + " px";
  }
  return {};
}

std::string CheckDetection(const Detection& d) {
  if (d.scene_id < 0 || d.image_id < 0) return "scene_id and image_id must be >= 0";
  if (d.obj_id < 1) return "category_id must be a positive integer";
  if (std::string problem = CheckDetectionBox(d); !problem.empty()) return problem;
  if (!std::isfinite(d.time_s)) return "time must be finite";
  return {};
}

std::string BoxText(const Detection& d) {
  return "[" + Number(d.x) + ", " + Number(d.y) + ", " + Number(d.w) + ", " + Number(d.h) + "]";
}

StatusOr<std::vector<Detection>> ReadDetectionsJson(const std::string& path) {
  try {
    MCPOSE_ASSIGN_OR_RETURN(json root, io::ReadJsonFile(path));
    if (!root.is_array()) return InvalidArgument(path + ": expected a JSON list of detections");
    std::vector<Detection> detections(root.size());
    for (size_t i = 0; i < root.size(); ++i) {
      const std::string problem = ParseEntry(root[i], &detections[i]);
      if (!problem.empty()) {
        return InvalidArgument(path + ": entry " + std::to_string(i) + ": " + problem);
      }
    }
    return detections;
  } catch (const std::exception& e) {
    return Internal(path + ": cannot read detections (" + e.what() + ")");
  }
}

Status WriteDetectionsJson(const std::string& path, const std::vector<Detection>& detections) {
  try {
    // One entry per line; numbers in shortest round-trip form.
    std::string text = "[";
    for (size_t i = 0; i < detections.size(); ++i) {
      const Detection& d = detections[i];
      const std::string problem = CheckDetection(d);
      if (!problem.empty()) {
        return InvalidArgument(path + ": detection " + std::to_string(i) + ": " + problem);
      }
      json entry = {{"scene_id", d.scene_id}, {"image_id", d.image_id}, {"category_id", d.obj_id},
                    {"score", d.score},       {"bbox", {d.x, d.y, d.w, d.h}}};
      if (d.time_s >= 0) entry["time"] = d.time_s;
      text += (i ? ",\n " : "\n ") + entry.dump();
    }
    text += detections.empty() ? "]\n" : "\n]\n";
    return io::WriteFileAtomic(path, text);
  } catch (const std::exception& e) {
    return Internal(path + ": cannot write detections (" + e.what() + ")");
  }
}

}  // namespace mcpose

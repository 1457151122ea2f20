// 2D detections in the BOP default-detections format.
#pragma once

#include <string>
#include <vector>

#include "mcpose/camera.h"
#include "mcpose/status.h"

namespace mcpose {

struct Detection {
  int scene_id = 0;
  int image_id = 0;
  int obj_id = 0;        // = category_id
  double score = 0;      // detector confidence in [0, 1]
  double x = 0, y = 0;   // top-left corner of the box, pixels (BOP "bbox": [x, y, w, h])
  double w = 0, h = 0;   // box size, pixels
  double time_s = -1;    // detector time for the image, < 0 if absent
};

// "[x, y, w, h]" of a detection's box, each number in %g form (6 significant digits), for
// messages.
std::string BoxText(const Detection& d);

// Empty if `d` is a valid detection (ids >= 0, category_id >= 1, score in [0, 1], a box of
// positive finite size within limits::kMaxBoxPx, finite time), else what is wrong with it. The
// detections reader and the Python entry points check each detection here.
std::string CheckDetection(const Detection& d);
// The part of that check about the box alone (its score and bbox), whatever its ids.
std::string CheckDetectionBox(const Detection& d);

// Intersection over union of two boxes; 0 when either is empty.
double BoxIou(const Detection& a, const Detection& b);

// Ok, or an error saying what is wrong with the box in an image of K's size: what
// CheckDetectionBox says, or a box that lies outside the image. The one check of a box, whether
// it comes from a file, the command line or Python.
Status CheckBox(const Detection& d, const Intrinsics& K);

// Reads a BOP detections JSON file: a list of {"scene_id", "image_id", "category_id", "score",
// "bbox": [x, y, w, h], "time" (optional)}. Errors name the file and the offending entry.
StatusOr<std::vector<Detection>> ReadDetectionsJson(const std::string& path);

// Writes the same format. Written to a temporary file and renamed: no partial file on error.
Status WriteDetectionsJson(const std::string& path, const std::vector<Detection>& detections);

}  // namespace mcpose

// The visual report: a static folder (index.html, images/*.png, plots as inline SVG) that shows
// every pose on its frame, its error, its depth residual and how the filter converged, with
// the worst objects first. It opens from disk: no script, no network.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "mcpose/dataset.h"
#include "mcpose/detection.h"
#include "mcpose/eval.h"
#include "mcpose/results.h"
#include "mcpose/status.h"
#include "mcpose/estimate_detail.h"

namespace mcpose::report {

struct ReportInput {
  std::vector<PoseResult> results;
  std::string results_path;  // shown in the page and named in errors
  std::optional<std::vector<Detection>> detections;
  std::string detections_path;
  std::optional<EstimateDetail> detail;
  std::string detail_path;
  bool draw_ground_truth = false;  // the ground-truth outlines, dashed
  EvalOptions eval;
  double residual_limit_m = 0.02;  // the depth-residual map spans [-limit, +limit]
  double inlier_m = 0.01;          // depth agreement counted within this
};

struct ReportSummary {
  int images = 0;
  int objects = 0;      // object entries (a ground-truth instance, a result, or both)
  int distractors = 0;  // boxes marked as distractors
  int64_t bytes = 0;    // all files of the folder
};

// Writes the report into `out_dir`: into a temporary folder beside it first, which replaces
// `out_dir` at the end, so a failed run leaves no partial report. An existing `out_dir` must be
// an earlier report (its .mcpose-report lists every file in it) or empty; its parent folder must
// exist. The run holds `out_dir`.lock (io::FileLock) throughout: a second report into the same
// folder at the same time is refused. Errors name
// the file and the problem: a detail entry whose pose differs from the results row of its
// object (another run), a results row or box of an image or class the dataset does not have,
// an unreadable frame or model.
StatusOr<ReportSummary> WriteReport(const Dataset& dataset, const ReportInput& input, const std::string& out_dir);

// The accuracy curve acc(x) = share of errors < x on [0, max_m] as a staircase of (x, share)
// points, from (0, 0) to (max_m, share below max_m); infinite errors never count.
std::vector<std::array<double, 2>> AccuracyCurve(std::vector<double> errors_m, double max_m);

// A box of an object class that holds no visible pixel of any ground-truth instance of that
// class (`visible_masks`: the visible masks of the class's instances in the box's image).
bool IsDistractor(const Detection& box, std::span<const MaskImage> visible_masks);

// The colour the report gives an object class, as RGBA and as CSS.
Rgba8 ObjectColour(int obj_id);
std::string CssColour(Rgba8 c);

}  // namespace mcpose::report

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

#include "cli/common.h"
#include "commands.h"
#include "mcpose/dataset.h"
#include "mcpose/detection.h"
#include "mcpose/results.h"
#include "mcpose/report.h"

namespace mcpose::cli {

namespace {

struct ReportArgs {
  std::string dataset, split = "test", results, detections, detail, out;
  bool gt = false;
  double auc_max_m = 0.10;
};

Status RunReport(const ReportArgs& a) {
  if (!(std::isfinite(a.auc_max_m) && a.auc_max_m > 0)) return InvalidArgument("--auc-max must be > 0");
  const auto start = std::chrono::steady_clock::now();
  MCPOSE_RETURN_IF_ERROR(CheckOutputsDistinct({{"--results", a.results}, {"--detections", a.detections}, {"--detail", a.detail}},
                                             {{"--out", a.out}}));
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<Dataset> dataset, Dataset::Open(a.dataset, a.split));
  MCPOSE_RETURN_IF_ERROR(CheckOutputsOutsideDataset(*dataset, {{"--out", a.out}}));
  report::ReportInput input;
  MCPOSE_ASSIGN_OR_RETURN(input.results, ReadResultsCsv(a.results));
  input.results_path = a.results;
  if (!a.detections.empty()) {
    MCPOSE_ASSIGN_OR_RETURN(input.detections, ReadDetectionsJson(a.detections));
    input.detections_path = a.detections;
  }
  if (!a.detail.empty()) {
    MCPOSE_ASSIGN_OR_RETURN(input.detail, report::ReadEstimateDetail(a.detail));
    input.detail_path = a.detail;
  }
  input.draw_ground_truth = a.gt;
  input.eval.auc_max_m = a.auc_max_m;
  MCPOSE_ASSIGN_OR_RETURN(report::ReportSummary summary, report::WriteReport(*dataset, input, a.out));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("report: %d image%s, %d objects, %.1f MB in %.1f s: open %s/index.html\n", summary.images,
              summary.images == 1 ? "" : "s", summary.objects, static_cast<double>(summary.bytes) / 1e6, seconds,
              a.out.c_str());
  return Status::Ok();
}

}  // namespace

void AddReportCommand(CLI::App& app, Status* status) {
  auto args = std::make_shared<ReportArgs>();
  CLI::App* cmd = app.add_subcommand(
      "report", "A static HTML report (index.html and PNG images) of results: each pose drawn on its frame, its "
                "error, depth residual and convergence, worst first");
  cmd->add_option("--dataset", args->dataset, "Dataset root (YCB-Video native or BOP layout)")->required();
  cmd->add_option("--split", args->split, "BOP split folder")->capture_default_str();
  cmd->add_option("--results", args->results, "Results CSV in the BOP format")->required();
  cmd->add_option("--detections", args->detections,
                  "The detections the results came from: boxes drawn, distractors marked, only their images shown");
  cmd->add_option("--detail", args->detail,
                  "The --out-json file of the same estimate run: chosen boxes and convergence plots");
  cmd->add_flag("--gt", args->gt, "Also draw the ground-truth outlines (dashed)");
  cmd->add_option("--auc-max", args->auc_max_m, "Upper end of the accuracy curves and AUC, metres")->capture_default_str();
  cmd->add_option("--out", args->out,
                  "Report folder to write (replaced if it holds an earlier report; its parent must exist)")
      ->required();
  cmd->callback([args, status] { *status = RunReport(*args); });
}

}  // namespace mcpose::cli

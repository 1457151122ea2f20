#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "cli/common.h"
#include "mcpose/estimate_detail.h"
#include "mcpose/io_util.h"
#include "commands.h"
#include "mcpose/run.h"
#include "mcpose/options_json.h"
#include "mcpose/results_journal.h"
#include "mcpose/bop19.h"
#include "mcpose/dataset.h"
#include "mcpose/detection.h"
#include "mcpose/results.h"

namespace mcpose::cli {

namespace {

struct EstimateArgs {
  std::string dataset, split = "test", models, detections, targets, out, out_json;
  std::vector<int> scenes;
  double min_score = 0;
  bool quiet = false, resume = false;
  EstimatorFlags flags;
};

Status RunEstimate(EstimateArgs& a) {
  MCPOSE_RETURN_IF_ERROR(a.flags.Finish());
  const EstimatorOptions& o = a.flags.options;

  // ---- Inputs and outputs, checked before any work -------------------------------------
  MCPOSE_RETURN_IF_ERROR(CheckOutputsDistinct({{"--detections", a.detections}, {"--targets", a.targets}},
                                              {{"--out", a.out}, {"--out-json", a.out_json}}));
  MCPOSE_RETURN_IF_ERROR(CheckWritable(a.out));
  if (!a.out_json.empty()) MCPOSE_RETURN_IF_ERROR(CheckWritable(a.out_json));
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<Dataset> dataset, Dataset::Open(a.dataset, a.split, a.models));
  MCPOSE_RETURN_IF_ERROR(CheckOutputsOutsideDataset(*dataset, {{"--out", a.out}, {"--out-json", a.out_json}}));
  MCPOSE_ASSIGN_OR_RETURN(std::vector<Detection> detections, ReadDetectionsJson(a.detections));
  if (detections.empty()) return InvalidArgument(a.detections + ": holds no detections");
  if (!a.scenes.empty()) {
    std::erase_if(detections, [&](const Detection& d) {
      return std::find(a.scenes.begin(), a.scenes.end(), d.scene_id) == a.scenes.end();
    });
    if (detections.empty()) return InvalidArgument(a.detections + ": holds no detections of the scenes given by --scene");
  }
  MCPOSE_RETURN_IF_ERROR(KeepScoresAtLeast(a.min_score, a.detections, &detections));
  // BOP's targets: each (image, class) they name holds inst_count instances. A BOP dataset's
  // own test_targets_bop19.json counts for its test split, as in mcpose eval.
  if (a.targets.empty() && dataset->format() == DatasetFormat::kBop && a.split == "test") {
    std::error_code ec;
    const std::string own = dataset->root() + "/test_targets_bop19.json";
    if (std::filesystem::is_regular_file(own, ec)) {
      a.targets = own;
      if (!a.quiet) spdlog::info("instances per (image, class) from {}", own);
    }
  }
  InstanceCounts instance_counts;
  std::string counts_text;
  if (!a.targets.empty()) {
    MCPOSE_ASSIGN_OR_RETURN(const std::vector<Bop19Target> targets, ReadBop19Targets(a.targets));
    for (const Bop19Target& t : targets) {
      instance_counts[{t.key, t.obj_id}] = t.inst_count;
      counts_text += std::to_string(t.key.scene_id) + " " + std::to_string(t.key.image_id) + " " + std::to_string(t.obj_id) +
                     " " + std::to_string(t.inst_count) + "\n";
    }
  }

  if (a.resume && !a.out_json.empty())
    return InvalidArgument("--out-json cannot be combined with --resume: the detail of the images an earlier run "
                           "finished is not kept");
  // Each finished image goes to the journal OUT.partial at once; the CSV is written at the end.
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<io::ResultsJournal> journal,
                          io::ResultsJournal::Open(a.out,
                                                   io::RunFingerprint(o, detections,
                                                                      {a.dataset, a.split, dataset->models_dir(),
                                                                       counts_text}),
                                                   a.resume));
  MCPOSE_RETURN_IF_ERROR(journal->CheckKeptAgainst(detections));
  if (journal->kept_images() > 0 && !a.quiet)
    spdlog::info("resuming: {} finished images kept from {}", journal->kept_images(), io::JournalPath(a.out));

  // ---- Run ------------------------------------------------------------------------------
  auto progress = [&](int done, int total, const ObjectRecord& r) {
    if (a.quiet) return;
    spdlog::info("[{}/{}] scene {} image {} obj {:2d}{} {:<24} boxes {} it {:2d} best w {:.3f} mean w {:.3f} {:.2f} s",
                 done, total, r.key.scene_id, r.key.image_id, r.obj_id,
                 r.instance > 0 ? " #" + std::to_string(r.instance + 1) : std::string(), r.name, r.num_boxes,
                 r.estimate.iterations.size(), r.estimate.best_weight, r.estimate.final_mean_weight(), r.time_s);
  };
  const auto image_done = [&](const FrameKey& key, const std::vector<PoseResult>& rows) {
    return journal->Append(key, rows);
  };
  const auto skip = [&](const FrameKey& key) { return journal->Has(key); };
  MCPOSE_ASSIGN_OR_RETURN(RunReport report,
                          RunEstimation(*dataset, detections, a.detections, o, progress, image_done, skip,
                                        a.targets.empty() ? nullptr : &instance_counts));

  // ---- Outputs: written only after everything succeeded ---------------------------------
  if (!a.out_json.empty()) {
    const nlohmann::json doc = ::mcpose::report::EstimateDetailJson(report, o, a.dataset, dataset->models_dir(), a.detections);
    MCPOSE_RETURN_IF_ERROR(io::WriteFileAtomic(a.out_json, doc.dump(1) + "\n"));
  }
  if (Status written = journal->Finish(); !written.ok()) {
    RemoveOutput(a.out_json);  // no half of the outputs is left behind
    return written;
  }

  if (!a.quiet) {
    double total_s = 0;
    size_t iterations = 0;
    for (const auto& r : report.objects) total_s += r.time_s, iterations += r.estimate.iterations.size();
    size_t rows = 0;
    for (const auto& [key, image_rows] : journal->images()) rows += image_rows.size();
    std::string kept;
    if (journal->kept_images() > 0)
      kept = " (and " + std::to_string(journal->kept_images()) + " images kept from the journal)";
    std::printf("%zu objects estimated in %.1f s, %.1f ms per iteration%s; %zu result rows: %s\n",
                report.objects.size(), total_s, iterations ? 1000.0 * total_s / static_cast<double>(iterations) : 0.0,
                kept.c_str(), rows, a.out.c_str());
  }
  return Status::Ok();
}

}  // namespace

void AddEstimateCommand(CLI::App& app, Status* status) {
  auto args = std::make_shared<EstimateArgs>();
  CLI::App* cmd = app.add_subcommand("estimate", "Estimate the 6-DoF pose of each object instance from 2D detections");
  cmd->add_option("--dataset", args->dataset, "Dataset root (YCB-Video native or BOP layout, auto-detected)")->required();
  cmd->add_option("--split", args->split, "BOP split folder")->capture_default_str();
  cmd->add_option("--models", args->models,
                  "Models folder in the dataset's layout to read meshes (and their colour) from instead of the "
                  "dataset's own, e.g. one written by capture-appearance");
  cmd->add_option("--detections", args->detections, "BOP default-detections JSON")->required();
  cmd->add_option("--scene", args->scenes, "Estimate only the detections of this scene_id (may be repeated)");
  cmd->add_option("--min-score", args->min_score,
                  "Leave out boxes whose detector score is below this (default 0: every box, each weighed by its score)")
      ->capture_default_str();
  cmd->add_option("--targets", args->targets,
                  "BOP's test_targets_bop19.json: each (image, class) it names holds its inst_count instances "
                  "(overrides --max-instances there; default: a BOP dataset's own, for the test split)");
  cmd->add_option("--out", args->out, "Results CSV (BOP format: scene_id,im_id,obj_id,score,R,t,time)")->required();
  cmd->add_option("--out-json", args->out_json, "Per-object detail: chosen box, per-iteration weights and times, engine counters");
  AddEstimatorFlags(cmd, kAllOptions, &args->flags);
  cmd->add_flag("--resume", args->resume,
                "Continue a run that was killed: keep the images its journal OUT.partial finished, estimate the rest");
  cmd->add_flag("-q,--quiet", args->quiet, "No progress output");
  cmd->callback([args, status] { *status = RunEstimate(*args); });
}

}  // namespace mcpose::cli

#include <cstdio>
#include <memory>

#include "mcpose/capture.h"
#include "cli/common.h"
#include "commands.h"
#include "mcpose/io_util.h"
#include "mcpose/dataset.h"

namespace mcpose::cli {

namespace {

struct CaptureArgs {
  std::string dataset, split = "test", out;
  std::vector<std::string> frame_lists;
  bool replace_own_colour = false;
  appearance::CaptureOptions options;
};

// The frames of the list files: one frame name a line (Dataset::ParseFrameName), blank lines
// and '#' comments skipped; errors name the file and the line.
StatusOr<std::vector<FrameKey>> ReadFrameLists(const Dataset& dataset, const std::vector<std::string>& paths) {
  std::vector<FrameKey> keys;
  for (const std::string& path : paths) {
    MCPOSE_ASSIGN_OR_RETURN(std::string text, io::ReadFileToString(path));
    int line_number = 0;
    for (std::string_view line : io::SplitLines(text)) {
      ++line_number;
      const std::string_view name = io::Trim(line);
      if (name.empty() || name.front() == '#') continue;
      StatusOr<FrameKey> key = dataset.ParseFrameName(std::string(name));
      if (!key.ok()) return Status(key.status().code(), path + ": line " + std::to_string(line_number) + ": " + key.status().message());
      if (std::find(keys.begin(), keys.end(), *key) == keys.end()) keys.push_back(*key);
    }
  }
  if (keys.empty()) return InvalidArgument("the frame lists name no frame");
  return keys;
}

Status RunCapture(const CaptureArgs& a) {
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<Dataset> dataset, Dataset::Open(a.dataset, a.split));
  MCPOSE_RETURN_IF_ERROR(CheckOutputsOutsideDataset(*dataset, {{"--out", a.out}}));
  MCPOSE_ASSIGN_OR_RETURN(std::vector<FrameKey> frames, ReadFrameLists(*dataset, a.frame_lists));
  MCPOSE_ASSIGN_OR_RETURN(std::vector<appearance::ObjectCapture> report,
                          appearance::CaptureDataset(*dataset, frames, a.options, a.replace_own_colour, a.out));
  std::printf("%zu frames; models written to %s\n", frames.size(), a.out.c_str());
  std::printf("%-24s %-10s %6s %9s %8s\n", "object", "colour", "views", "samples", "seen");
  for (const auto& o : report) {
    const char* source = o.source == appearance::ObjectCapture::Source::kCaptured   ? "captured"
                         : o.source == appearance::ObjectCapture::Source::kOwnColour ? "own"
                                                                                     : "none";
    if (o.source == appearance::ObjectCapture::Source::kCaptured) {
      std::printf("%-24s %-10s %6d %9lld %7.1f%%\n", o.name.c_str(), source, o.stats.views,
                  static_cast<long long>(o.stats.samples), 100.0 * o.stats.known / std::max(1, o.stats.points));
    } else {
      std::printf("%-24s %-10s\n", o.name.c_str(), source);
    }
  }
  return Status::Ok();
}

}  // namespace

void AddCaptureCommand(CLI::App& app, Status* status) {
  auto args = std::make_shared<CaptureArgs>();
  CLI::App* cmd = app.add_subcommand(
      "capture-appearance",
      "Bake each object's surface colour from posed frames (ground truth) into a models folder for --models");
  cmd->add_option("--dataset", args->dataset, "Dataset root (YCB-Video native or BOP layout)")->required();
  cmd->add_option("--split", args->split, "BOP split folder")->capture_default_str();
  cmd->add_option("--frames", args->frame_lists,
                  "File listing frames, one a line: VIDEO/FRAME or data_syn/FRAME (YCB-Video), SCENE/IMAGE (BOP); "
                  "may be given several times")->required();
  cmd->add_option("--out", args->out, "Models folder to write (the dataset's layout)")->required();
  cmd->add_option("--texture-size", args->options.texture_size, "Texels a side of a captured texture")->capture_default_str();
  cmd->add_option("--depth-agreement", args->options.depth_agreement_m,
                  "Use a pixel only where observed and rendered depth agree within this, metres")->capture_default_str();
  cmd->add_flag("--replace-own-colour", args->replace_own_colour,
                "Capture objects whose model has colour of its own too (default: keep theirs)");
  cmd->callback([args, status] { *status = RunCapture(*args); });
}

}  // namespace mcpose::cli

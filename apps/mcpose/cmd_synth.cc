#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "cli/common.h"
#include "commands.h"
#include "mcpose/json_util.h"
#include "mcpose/synth.h"

namespace mcpose::cli {

namespace {

struct SynthArgs {
  std::string models, out, camera;
  std::vector<int> objects = {3, 7};
  std::vector<double> distance = {0.5, 1.3};
  bool quiet = false;
  synth::SynthDatasetOptions options;
};

std::string DefaultModels() {
  const char* env = std::getenv("MCPOSE_DATA_DIR");
  return std::string(env && *env ? env : "../shared/data") + "/ycbv_textured/models";
}

// A camera from a BOP camera.json (fx, fy, cx, cy, width, height).
Status ReadCamera(const std::string& path, Intrinsics* K) {
  MCPOSE_ASSIGN_OR_RETURN(nlohmann::json doc, io::ReadJsonFile(path));
  try {
    K->fx = doc.at("fx").get<double>(), K->fy = doc.at("fy").get<double>();
    K->cx = doc.at("cx").get<double>(), K->cy = doc.at("cy").get<double>();
    K->width = doc.at("width").get<int>(), K->height = doc.at("height").get<int>();
  } catch (const std::exception& e) {
    return InvalidArgument(path + ": expected a BOP camera.json with fx, fy, cx, cy, width, height (" + e.what() + ")");
  }
  std::string error;
  if (!K->IsValid(&error)) return InvalidArgument(path + ": " + error);
  return Status::Ok();
}

Status RunSynth(SynthArgs& a) {
  synth::SceneOptions& s = a.options.scene;
  if (a.objects.size() != 2) return InvalidArgument("--objects takes two numbers, the least and the most a frame");
  if (a.distance.size() != 2) return InvalidArgument("--distance takes two numbers, metres");
  s.min_objects = a.objects[0], s.max_objects = a.objects[1];
  s.min_distance_m = a.distance[0], s.max_distance_m = a.distance[1];
  if (!a.camera.empty()) MCPOSE_RETURN_IF_ERROR(ReadCamera(a.camera, &s.camera));
  std::string error;
  if (!a.options.IsValid(&error)) return InvalidArgument("invalid synth options: " + error);
  // Before reading the models, which takes seconds for textured ones.
  MCPOSE_RETURN_IF_ERROR(synth::CheckSynthOutFolder(a.out));
  MCPOSE_ASSIGN_OR_RETURN(std::vector<synth::NamedModel> models, synth::LoadModelsFolder(a.models));
  const auto progress = [&a](int done, int total) {
    if (a.quiet) return;
    std::fprintf(stderr, "\rframes %d/%d", done, total);
    if (done == total) std::fprintf(stderr, "\n");
  };
  MCPOSE_RETURN_IF_ERROR(synth::WriteSynthDataset(models, a.options, a.out, progress));
  std::printf("%d frames of %zu models written to %s (BOP layout; boxes in %s/detections.json)\n", a.options.frames,
              models.size(), a.out.c_str(), a.out.c_str());
  return Status::Ok();
}

}  // namespace

void AddSynthCommand(CLI::App& app, Status* status) {
  auto args = std::make_shared<SynthArgs>();
  args->models = DefaultModels();
  CLI::App* cmd = app.add_subcommand(
      "synth",
      "A synthetic stress set in the BOP layout: objects at rest on a table, rendered with their textures, a "
      "structured-light depth sensor's noise and gaps, random light, and detector-like boxes");
  cmd->add_option("--models", args->models,
                  "Models folder (YCB-Video layout, <name>/textured_simple.obj, or BOP layout, obj_NNNNNN.ply)")
      ->capture_default_str();
  cmd->add_option("--out", args->out, "Dataset folder to write (must not exist); written whole or not at all")
      ->required();
  cmd->add_option("--frames", args->options.frames, "Frames to make")->capture_default_str();
  cmd->add_option("--seed", args->options.seed, "Seed: the same seed, the same dataset")
      ->check(SeedCheck())
      ->capture_default_str();
  cmd->add_option("--objects", args->objects, "The least and the most objects a frame")->expected(2)->capture_default_str();
  cmd->add_option("--copies", args->options.scene.copies,
                  "The first object of each frame appears this many times, side by side (several instances of one "
                  "class)")
      ->capture_default_str();
  cmd->add_option("--distance", args->distance, "Nearest and farthest object from the camera, metres")
      ->expected(2)
      ->capture_default_str();
  cmd->add_option("--side-share", args->options.scene.side_share,
                  "Share of objects resting on another stable face than their lowest (lying on a side)")
      ->capture_default_str();
  cmd->add_option("--min-visible", args->options.scene.min_visible,
                  "Objects hidden by others below this visible fraction are taken out of the frame")
      ->capture_default_str();
  cmd->add_option("--camera", args->camera, "A BOP camera.json to take the intrinsics from (default: YCB-Video's)");
  cmd->add_option("--depth-noise", args->options.scene.depth_noise,
                  "Depth noise sigma at z metres: this * z^2 (metres per square metre)")
      ->capture_default_str();
  cmd->add_option("--colour-noise", args->options.scene.colour_noise, "Colour noise sigma, 8-bit levels")
      ->capture_default_str();
  cmd->add_option("--jpeg", args->options.scene.jpeg_quality,
                  "Pass each colour image through JPEG of this quality; 0: none")
      ->capture_default_str();
  cmd->add_option("--jitter", args->options.detections.jitter, "Boxes: each side moved by up to this share of the box")
      ->capture_default_str();
  cmd->add_option("--distractors", args->options.detections.distractors,
                  "Boxes: probability of an extra wrong box of the same class")
      ->capture_default_str();
  cmd->add_flag("-q,--quiet", args->quiet, "No progress on stderr");
  cmd->callback([args, status] { *status = RunSynth(*args); });
}

}  // namespace mcpose::cli

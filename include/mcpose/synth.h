// A synthetic dataset in the BOP layout (synth/scene.h makes its frames): what `mcpose synth`
// writes, and what `mcpose estimate`, `eval` and the other commands read like any BOP dataset.
//
//   OUT/camera.json
//   OUT/models/models_info.json, obj_NNNNNN.ply   (mm; the models' geometry, vertex colours if any)
//   OUT/test/000000/scene_camera.json, scene_gt.json, scene_gt_info.json
//   OUT/test/000000/rgb/IIIIII.png, depth/IIIIII.png (0.1 mm units), mask_visib/IIIIII_GGGGGG.png
//   OUT/detections.json                           (boxes as `mcpose detections-from-gt` makes them)
// Images are numbered from 1. A textured model's colour stays in its own folder: estimate with
// `--models` naming that folder (a YCB-Video models folder serves a BOP dataset of its objects).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "mcpose/eval.h"
#include "mcpose/mesh.h"
#include "mcpose/status.h"
#include "mcpose/synth_scene.h"

namespace mcpose::synth {

struct NamedModel {
  int obj_id = 0;
  std::string name;
  Mesh mesh;
};

// The models of a folder in the YCB-Video layout (<name>/textured_simple.obj, obj_id = the
// name's YCB-Video class index) or the BOP layout (models_info.json and obj_NNNNNN.ply in mm).
StatusOr<std::vector<NamedModel>> LoadModelsFolder(const std::string& dir);

struct SynthDatasetOptions {
  int frames = 100;
  uint64_t seed = 0;
  SceneOptions scene;
  GtDetectionOptions detections;  // its seed is replaced by `seed`
  bool IsValid(std::string* error) const;
};

// Whether `out_dir` can be written: it must not exist, and its parent folder must. WriteSynthDataset
// checks it again; a caller checks it first to fail before loading the models.
Status CheckSynthOutFolder(const std::string& out_dir);

// Writes the dataset to `out_dir`, which must not exist: into a fresh folder beside it, renamed
// into place when every file is written, so that a failed run leaves nothing. `progress` (may be
// null) after each frame.
Status WriteSynthDataset(const std::vector<NamedModel>& models, const SynthDatasetOptions& options,
                         const std::string& out_dir, const std::function<void(int done, int total)>& progress = {});

}  // namespace mcpose::synth

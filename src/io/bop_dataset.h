// The BOP layout (bop_toolkit docs/bop_datasets_format.md): models/models_info.json,
// models/obj_NNNNNN.ply (mm), <split>/<scene>/{scene_camera,scene_gt}.json, depth/NNNNNN.png,
// mask_visib/NNNNNN_NNNNNN.png. Units in the files: mm (cam_t_m2c, models) and
// depth_mm = value * depth_scale; everything is returned in metres.
#pragma once

#include <memory>
#include <string>

#include "mcpose/dataset.h"
#include "mcpose/status.h"

namespace mcpose::io {

// Opens a BOP dataset: reads models_info.json, the optional root camera.json (image size,
// default depth_scale) and every <split>/<6-digit scene>/scene_gt.json (the frames). Scene
// folders without scene_gt.json are skipped. scene_camera.json is read when a frame is loaded.
// Meshes are read from `models_dir`/obj_NNNNNN.ply.
StatusOr<std::unique_ptr<Dataset>> OpenBopDataset(const std::string& root, const std::string& split,
                                                  const std::string& models_dir);

}  // namespace mcpose::io

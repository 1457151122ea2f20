// The YCB-Video native layout (data/<video>/<frame>-{depth,label}.png, -meta.mat; classes.txt;
// models/<name>/{textured_simple.obj,points.xyz}). Units in the files: metres, except depth
// (value / factor_depth metres).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mcpose/dataset.h"
#include "mcpose/se3.h"
#include "mcpose/status.h"

namespace mcpose::io {

// The parts of a YCB-Video -meta.mat that mcpose uses.
struct YcbvMeta {
  Eigen::Matrix3d K = Eigen::Matrix3d::Zero();  // intrinsic_matrix (not validated here)
  double factor_depth = 0;                      // depth units per metre
  std::vector<int> cls_indexes;                 // obj_id of each pose
  std::vector<SE3> poses;                       // T_cam_obj, metres, same order
};

// Reads intrinsic_matrix (3x3), factor_depth (any numeric class), poses (3x4xN or 3x4 for
// N = 1; double or single) and cls_indexes (any numeric class, Nx1 or 1xN) with libmatio.
// Errors name `path` and the variable: missing, wrong shape, non-numeric, non-finite.
StatusOr<YcbvMeta> ReadYcbvMeta(const std::string& path);

// Writes the same variables (intrinsic_matrix, factor_depth and poses as double, cls_indexes as
// uint8 Nx1) to a MATLAB 5 MAT-file, for tests and tools. Written to `path` + ".tmp", renamed.
Status WriteYcbvMeta(const std::string& path, const YcbvMeta& meta);

// Opens a YCB-Video folder: reads classes.txt and lists data/<4 digits>/<6 digits>-meta.mat
// (the frames) and data_syn/<6 digits>-meta.mat (synthetic frames, scene kSyntheticScene, not
// among Frames()). Meshes are read from `models_dir`/<name>/textured_simple.obj.
StatusOr<std::unique_ptr<Dataset>> OpenYcbvDataset(const std::string& root, const std::string& models_dir);

// Points of a points.xyz file ("x y z" per line, metres).
StatusOr<std::vector<Eigen::Vector3f>> ReadXyzPoints(const std::string& path);

}  // namespace mcpose::io

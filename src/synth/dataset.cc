#include "mcpose/synth.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <nlohmann/json.hpp>

#include "mcpose/io_util.h"
#include "mcpose/json_util.h"
#include "io/obj_io.h"
#include "io/ply_io.h"
#include "mcpose/png_io.h"
#include "io/ycbv_names.h"
#include "mcpose/dataset.h"
#include "mcpose/detection.h"

namespace mcpose::synth {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string Id6(int id) {
  char text[16];
  std::snprintf(text, sizeof text, "%06d", id);
  return text;
}

json Row(const Eigen::Matrix3d& R) {
  json out = json::array();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out.push_back(R(r, c));
  return out;
}

json Mm(const Eigen::Vector3d& t) { return json::array({1000 * t.x(), 1000 * t.y(), 1000 * t.z()}); }

// The largest distance between two vertices of the mesh (BOP's diameter), mm.
double DiameterMm(const Mesh& mesh) {
  double best = 0;
  const auto& v = mesh.vertices_m;
  for (size_t i = 0; i < v.size(); ++i)
    for (size_t j = i + 1; j < v.size(); ++j) best = std::max(best, static_cast<double>((v[i] - v[j]).squaredNorm()));
  return 1000 * std::sqrt(best);
}

Status WriteJson(const fs::path& path, const json& doc) { return io::WriteFileAtomic(path.string(), doc.dump(1) + "\n"); }

Status WriteAll(const std::vector<NamedModel>& models, const SynthDatasetOptions& o, const fs::path& root,
                const std::function<void(int, int)>& progress) {
  std::error_code ec;
  const fs::path scene = root / "test" / Id6(0);
  for (const fs::path& d : {root / "models", scene / "rgb", scene / "depth", scene / "mask_visib"}) {
    fs::create_directories(d, ec);
    if (ec) return Internal(d.string() + ": cannot create folder (" + ec.message() + ")");
  }
  // ---- Models and camera --------------------------------------------------------------------
  json info = json::object();
  for (const NamedModel& m : models) {
    MCPOSE_RETURN_IF_ERROR(io::WritePlyMesh((root / "models" / ("obj_" + Id6(m.obj_id) + ".ply")).string(), m.mesh, 1000.0));
    const Eigen::Vector3f lo = m.mesh.BoundsMin(), hi = m.mesh.BoundsMax();
    info[std::to_string(m.obj_id)] = {{"diameter", DiameterMm(m.mesh)},
                                      {"min_x", 1000 * lo.x()}, {"min_y", 1000 * lo.y()}, {"min_z", 1000 * lo.z()},
                                      {"size_x", 1000 * (hi - lo).x()}, {"size_y", 1000 * (hi - lo).y()},
                                      {"size_z", 1000 * (hi - lo).z()}};
  }
  MCPOSE_RETURN_IF_ERROR(WriteJson(root / "models" / "models_info.json", info));
  const Intrinsics& K = o.scene.camera;
  MCPOSE_RETURN_IF_ERROR(WriteJson(root / "camera.json", {{"cx", K.cx}, {"cy", K.cy}, {"fx", K.fx}, {"fy", K.fy},
                                                          {"width", K.width}, {"height", K.height}, {"depth_scale", 0.1}}));
  // ---- Frames ---------------------------------------------------------------------------------
  std::vector<SceneObject> objects;
  for (const NamedModel& m : models) objects.push_back({m.obj_id, &m.mesh});
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<SceneMaker> maker, SceneMaker::Create(objects, o.scene, o.seed));
  json cameras = json::object(), gts = json::object(), infos = json::object();
  for (int f = 0; f < o.frames; ++f) {
    MCPOSE_ASSIGN_OR_RETURN(SynthFrame frame, maker->MakeFrame(f));
    const int im_id = f + 1;
    const std::string name = Id6(im_id);
    MCPOSE_RETURN_IF_ERROR(io::WriteColourPng((scene / "rgb" / (name + ".png")).string(), frame.colour));
    io::Gray16Image depth;
    depth.width = K.width, depth.height = K.height;
    depth.values = frame.depth;
    MCPOSE_RETURN_IF_ERROR(io::WriteGray16Png((scene / "depth" / (name + ".png")).string(), depth));
    const json cam_K = {K.fx, 0.0, K.cx, 0.0, K.fy, K.cy, 0.0, 0.0, 1.0};
    cameras[std::to_string(im_id)] = {{"cam_K", cam_K}, {"depth_scale", 0.1},
                                      {"cam_R_w2c", Row(frame.T_cam_world.R)}, {"cam_t_w2c", Mm(frame.T_cam_world.t)}};
    json gt = json::array(), gi = json::array();
    for (size_t g = 0; g < frame.instances.size(); ++g) {
      const SynthInstance& s = frame.instances[g];
      gt.push_back({{"obj_id", s.obj_id}, {"cam_R_m2c", Row(s.T_cam_obj.R)}, {"cam_t_m2c", Mm(s.T_cam_obj.t)}});
      gi.push_back({{"bbox_obj", {s.bbox_obj[0], s.bbox_obj[1], s.bbox_obj[2], s.bbox_obj[3]}},
                    {"bbox_visib", {s.bbox_visib[0], s.bbox_visib[1], s.bbox_visib[2], s.bbox_visib[3]}},
                    {"px_count_all", s.px_count_all}, {"px_count_valid", s.px_count_valid},
                    {"px_count_visib", s.px_count_visib}, {"visib_fract", s.visib_fract()}});
      MCPOSE_RETURN_IF_ERROR(
          io::WriteMaskPng((scene / "mask_visib" / (name + "_" + Id6(static_cast<int>(g)) + ".png")).string(), s.visible));
    }
    gts[std::to_string(im_id)] = gt;
    infos[std::to_string(im_id)] = gi;
    if (progress) progress(f + 1, o.frames);
  }
  MCPOSE_RETURN_IF_ERROR(WriteJson(scene / "scene_camera.json", cameras));
  MCPOSE_RETURN_IF_ERROR(WriteJson(scene / "scene_gt.json", gts));
  MCPOSE_RETURN_IF_ERROR(WriteJson(scene / "scene_gt_info.json", infos));
  // ---- Boxes, from the dataset as written ------------------------------------------------------
  MCPOSE_ASSIGN_OR_RETURN(std::unique_ptr<Dataset> written, Dataset::Open(root.string()));
  GtDetectionOptions d = o.detections;
  d.seed = o.seed;
  MCPOSE_ASSIGN_OR_RETURN(std::vector<Detection> boxes, DetectionsFromGroundTruth(*written, d));
  return WriteDetectionsJson((root / "detections.json").string(), boxes);
}

}  // namespace

bool SynthDatasetOptions::IsValid(std::string* error) const {
  if (frames < 1 || frames > 100000) {
    if (error) *error = "frames must lie in [1, 100000]";
    return false;
  }
  if (!(detections.jitter >= 0 && detections.jitter <= 1) || !(detections.distractors >= 0 && detections.distractors <= 1)) {
    if (error) *error = "jitter and distractors must lie in [0, 1]";
    return false;
  }
  return scene.IsValid(error);
}

StatusOr<std::vector<NamedModel>> LoadModelsFolder(const std::string& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return NotFound(dir + ": models folder does not exist");
  std::vector<NamedModel> out;
  const std::vector<std::string>& names = io::YcbvClassNames();
  for (size_t i = 0; i < names.size(); ++i) {
    const std::string obj = dir + "/" + names[i] + "/textured_simple.obj";
    if (!fs::is_regular_file(obj, ec)) continue;
    MCPOSE_ASSIGN_OR_RETURN(Mesh mesh, io::ReadObjMesh(obj));
    out.push_back({static_cast<int>(i) + 1, names[i], std::move(mesh)});
  }
  if (!out.empty()) return out;
  const std::string info_path = dir + "/models_info.json";
  if (!fs::is_regular_file(info_path, ec))
    return InvalidArgument(dir + ": neither YCB-Video models (<name>/textured_simple.obj) nor BOP models (models_info.json)");
  MCPOSE_ASSIGN_OR_RETURN(json info, io::ReadJsonFile(info_path));
  if (!info.is_object() || info.empty()) return InvalidArgument(info_path + ": expected an object keyed by obj_id");
  for (const auto& [key, value] : info.items()) {
    int obj_id = 0;
    if (!io::ParseInt(key, &obj_id) || obj_id < 1) return InvalidArgument(info_path + ": key '" + key + "' is not an obj_id");
    MCPOSE_ASSIGN_OR_RETURN(Mesh mesh, io::ReadPlyMesh(dir + "/obj_" + Id6(obj_id) + ".ply", 1000.0));
    out.push_back({obj_id, "obj_" + Id6(obj_id), std::move(mesh)});
  }
  std::sort(out.begin(), out.end(), [](const NamedModel& a, const NamedModel& b) { return a.obj_id < b.obj_id; });
  return out;
}

Status CheckSynthOutFolder(const std::string& out_dir) {
  const fs::path out = fs::absolute(out_dir).lexically_normal();
  std::error_code ec;
  if (fs::exists(fs::symlink_status(out, ec))) return InvalidArgument(out_dir + ": already exists; synth writes a new folder");
  const fs::path parent = out.parent_path();
  if (!fs::is_directory(parent, ec)) return NotFound(out_dir + ": folder " + parent.string() + " does not exist");
  return Status::Ok();
}

Status WriteSynthDataset(const std::vector<NamedModel>& models, const SynthDatasetOptions& options,
                         const std::string& out_dir, const std::function<void(int, int)>& progress) {
  std::string error;
  if (!options.IsValid(&error)) return InvalidArgument("synth options: " + error);
  if (models.empty()) return InvalidArgument("no models to place");
  MCPOSE_RETURN_IF_ERROR(CheckSynthOutFolder(out_dir));
  const fs::path out = fs::absolute(out_dir).lexically_normal();
  std::error_code ec;
  MCPOSE_ASSIGN_OR_RETURN(const fs::path tmp, io::CreateFolderBeside(out.string(), ".tmp-"));
  Status status;
  try {
    status = WriteAll(models, options, tmp, progress);
  } catch (const std::exception& e) {
    status = Internal(out_dir + ": " + e.what());
  }
  if (status.ok()) {
    fs::rename(tmp, out, ec);
    if (ec) status = Internal(out_dir + ": cannot rename " + tmp.string() + " to it (" + ec.message() + ")");
  }
  if (!status.ok()) fs::remove_all(tmp, ec);
  return status;
}

}  // namespace mcpose::synth

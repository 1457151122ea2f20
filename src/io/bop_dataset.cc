#include "io/bop_dataset.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>

#include "mcpose/limits.h"
#include "mcpose/io_util.h"
#include "io/jpeg_io.h"
#include "mcpose/json_util.h"
#include "io/obj_io.h"
#include "io/ply_io.h"
#include "mcpose/png_io.h"
#include "io/ycbv_names.h"

namespace mcpose::io {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kMmPerMetre = 1000.0;

// "000049": the zero-padded ids of BOP file and folder names.
std::string Id6(int id) {
  char buffer[16];
  std::snprintf(buffer, sizeof(buffer), "%06d", id);
  return buffer;
}

bool AllDigits(const std::string& s) {
  return !s.empty() && s.size() <= 9 &&
         std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}


// One image's entry of scene_camera.json.
struct CameraEntry {
  double K[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};  // row-major cam_K
  std::optional<double> depth_scale;             // depth_mm = value * depth_scale
};
using SceneCameras = std::map<int, CameraEntry>;

// The root camera.json: image size and default depth scale (all optional).
struct DatasetCamera {
  int width = 0, height = 0;
  std::optional<double> depth_scale;
};

StatusOr<SceneCameras> ParseSceneCamera(const std::string& path) {
  MCPOSE_ASSIGN_OR_RETURN(json root, ReadJsonFile(path));
  if (!root.is_object()) return InvalidArgument(path + ": expected an object keyed by image id");
  SceneCameras cameras;
  for (const auto& [key, entry] : root.items()) {
    int im_id = 0;
    if (!IsIdKey(key) || !ParseInt(key, &im_id)) {
      return InvalidArgument(path + ": key '" + key + "' is not an image id (digits, no leading zero)");
    }
    const std::string where = path + ": image " + key + ": ";
    if (!entry.is_object() || !entry.contains("cam_K")) {
      return InvalidArgument(where + "missing cam_K");
    }
    CameraEntry camera;
    const json& K = entry["cam_K"];
    if (!K.is_array() || K.size() != 9) {
      return InvalidArgument(where + "cam_K must have 9 numbers (row-major 3x3)");
    }
    for (size_t i = 0; i < 9; ++i) {
      // JSON has no NaN/Infinity (the parser refuses them); IsValid still checks at load time.
      if (!K[i].is_number()) return InvalidArgument(where + "cam_K[" + std::to_string(i) + "] is not a number");
      camera.K[i] = K[i].get<double>();
    }
    for (const auto& [field, f] : {std::pair{"fx", camera.K[0]}, std::pair{"fy", camera.K[4]}}) {
      if (const std::string problem = limits::CheckFocal(field, f); !problem.empty())
        return InvalidArgument(where + "cam_K: " + problem);
    }
    if (entry.contains("depth_scale")) {
      double scale = 0;
      if (!JsonToDouble(entry["depth_scale"], &scale) || !(scale > 0)) {
        return InvalidArgument(where + "depth_scale must be a positive number");
      }
      if (const std::string problem = limits::CheckDepthScale(scale / kMmPerMetre); !problem.empty())
        return InvalidArgument(where + "depth_scale = " + limits::Num(scale) + " mm: " + problem);
      camera.depth_scale = scale;
    }
    cameras[im_id] = camera;
  }
  return cameras;
}

// scene_gt.json: per image id, a list of {obj_id, cam_R_m2c (row-major), cam_t_m2c (mm)}.
Status ParseSceneGt(const std::string& path, int scene_id,
                    std::map<FrameKey, std::vector<GtInstance>>* frames) {
  MCPOSE_ASSIGN_OR_RETURN(json root, ReadJsonFile(path));
  if (!root.is_object()) return InvalidArgument(path + ": expected an object keyed by image id");
  for (const auto& [key, list] : root.items()) {
    int im_id = 0;
    if (!IsIdKey(key) || !ParseInt(key, &im_id)) {
      return InvalidArgument(path + ": key '" + key + "' is not an image id (digits, no leading zero)");
    }
    if (!list.is_array()) return InvalidArgument(path + ": image " + key + ": expected a list");
    std::vector<GtInstance> gt;
    for (size_t i = 0; i < list.size(); ++i) {
      const json& entry = list[i];
      const std::string where = path + ": image " + key + ": entry " + std::to_string(i) + ": ";
      GtInstance instance;
      instance.gt_index = static_cast<int>(i);
      double R[9], t[3];
      if (!entry.is_object() || !entry.contains("obj_id") ||
          !JsonToInt(entry["obj_id"], &instance.obj_id) || instance.obj_id < 1) {
        return InvalidArgument(where + "obj_id must be a positive integer");
      }
      if (!entry.contains("cam_R_m2c") || !JsonToDoubles(entry["cam_R_m2c"], 9, R)) {
        return InvalidArgument(where + "cam_R_m2c must have 9 finite numbers");
      }
      if (!entry.contains("cam_t_m2c") || !JsonToDoubles(entry["cam_t_m2c"], 3, t)) {
        return InvalidArgument(where + "cam_t_m2c must have 3 finite numbers");
      }
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) instance.T_cam_obj.R(r, c) = R[3 * r + c];
        instance.T_cam_obj.t(r) = t[r] / kMmPerMetre;
      }
      if (const std::string problem = limits::CheckRotation(instance.T_cam_obj.R); !problem.empty())
        return InvalidArgument(where + "cam_R_m2c: " + problem);
      if (const std::string problem = limits::CheckCoordinates(instance.T_cam_obj.t); !problem.empty())
        return InvalidArgument(where + "cam_t_m2c: " + problem);
      gt.push_back(instance);
    }
    (*frames)[FrameKey{scene_id, im_id}] = std::move(gt);
  }
  return Status::Ok();
}

StatusOr<DatasetCamera> ParseDatasetCamera(const std::string& path) {
  DatasetCamera camera;
  std::error_code ec;
  if (!fs::exists(path, ec)) return camera;
  MCPOSE_ASSIGN_OR_RETURN(json root, ReadJsonFile(path));
  if (!root.is_object()) return InvalidArgument(path + ": expected an object");
  if (root.contains("width") || root.contains("height")) {
    if (!root.contains("width") || !root.contains("height") ||
        !JsonToInt(root["width"], &camera.width) || !JsonToInt(root["height"], &camera.height) ||
        camera.width <= 0 || camera.height <= 0 || camera.width > limits::kMaxImageSide ||
        camera.height > limits::kMaxImageSide) {
      return InvalidArgument(path + ": width and height must be integers in 1-" +
                             std::to_string(limits::kMaxImageSide));
    }
  }
  if (root.contains("depth_scale")) {
    double scale = 0;
    if (!JsonToDouble(root["depth_scale"], &scale) || !(scale > 0)) {
      return InvalidArgument(path + ": depth_scale must be a positive number");
    }
    if (const std::string problem = limits::CheckDepthScale(scale / kMmPerMetre); !problem.empty())
      return InvalidArgument(path + ": depth_scale = " + limits::Num(scale) + " mm: " + problem);
    camera.depth_scale = scale;
  }
  return camera;
}

class BopDataset final : public Dataset {
 public:
  BopDataset(std::string root, std::string split, std::string models_dir, std::vector<int> object_ids,
             DatasetCamera camera, std::map<int, std::string> scene_dirs,
             std::map<FrameKey, std::vector<GtInstance>> frames)
      : root_(std::move(root)),
        split_dir_(root_ + "/" + split),
        models_dir_(std::move(models_dir)),
        object_ids_(std::move(object_ids)),
        camera_(camera),
        scene_dirs_(std::move(scene_dirs)),
        frames_(std::move(frames)) {
    // The YCB-Video names apply when the models are exactly YCB-Video's 21 objects.
    const size_t n = YcbvClassNames().size();
    ycbv_ids_ = object_ids_.size() == n && object_ids_.front() == 1 &&
                object_ids_.back() == static_cast<int>(n);
  }

  DatasetFormat format() const override { return DatasetFormat::kBop; }
  const std::string& root() const override { return root_; }

  std::vector<FrameKey> Frames() const override {
    std::vector<FrameKey> keys;
    keys.reserve(frames_.size());
    for (const auto& [key, gt] : frames_) keys.push_back(key);
    return keys;
  }

  StatusOr<Intrinsics> LoadIntrinsics(const FrameKey& key) const override {
    if (frames_.find(key) == frames_.end()) return MissingFrame(key);
    const std::string depth_path = SceneDir(key.scene_id) + "/depth/" + Id6(key.image_id) + ".png";
    MCPOSE_ASSIGN_OR_RETURN(const ImageSize size, ReadPngSize(depth_path));
    return Camera(key, size.width, size.height, depth_path);
  }

  StatusOr<Frame> LoadFrame(const FrameKey& key) const override {
    const auto it = frames_.find(key);
    if (it == frames_.end()) return MissingFrame(key);
    const std::string scene_dir = SceneDir(key.scene_id);
    Frame frame;
    frame.key = key;
    frame.depth_path = scene_dir + "/depth/" + Id6(key.image_id) + ".png";
    // Depth: depth_mm = value * depth_scale; then the camera, checked against the depth's size.
    MCPOSE_ASSIGN_OR_RETURN(const double depth_scale, DepthScale(key));
    MCPOSE_ASSIGN_OR_RETURN(frame.depth, ReadDepthPng(frame.depth_path, depth_scale / kMmPerMetre));
    MCPOSE_ASSIGN_OR_RETURN(frame.K, Camera(key, frame.depth.width, frame.depth.height, frame.depth_path));
    // The colour image, where it is a PNG, must have the depth's size.
    const std::string rgb_path = scene_dir + "/rgb/" + Id6(key.image_id) + ".png";
    std::error_code rgb_ec;
    if (fs::exists(rgb_path, rgb_ec)) {
      MCPOSE_ASSIGN_OR_RETURN(const ImageSize size, ReadPngSize(rgb_path));
      if (size.width != frame.depth.width || size.height != frame.depth.height)
        return InvalidArgument(rgb_path + ": image is " + std::to_string(size.width) + "x" +
                               std::to_string(size.height) + " but the depth image " + frame.depth_path +
                               " of its frame is " + std::to_string(frame.depth.width) + "x" +
                               std::to_string(frame.depth.height));
    }
    frame.gt = it->second;
    return frame;
  }

  StatusOr<ColourImage> LoadColour(const Frame& frame) const override {
    if (frames_.find(frame.key) == frames_.end()) return MissingFrame(frame.key);
    // rgb/NNNNNN.png, or .jpg as some BOP datasets store them.
    const std::string stem = SceneDir(frame.key.scene_id) + "/rgb/" + Id6(frame.key.image_id);
    std::error_code ec;
    const std::string path = std::filesystem::exists(stem + ".png", ec) || !std::filesystem::exists(stem + ".jpg", ec)
                                 ? stem + ".png"
                                 : stem + ".jpg";
    MCPOSE_ASSIGN_OR_RETURN(ColourImage colour, ReadColourImage(path));
    if (colour.width != frame.depth.width || colour.height != frame.depth.height)
      return InvalidArgument(path + ": colour image is " + std::to_string(colour.width) + "x" +
                             std::to_string(colour.height) + " but the depth image " + frame.depth_path + " is " +
                             std::to_string(frame.depth.width) + "x" + std::to_string(frame.depth.height));
    for (size_t i = 3; i < colour.rgba.size(); i += 4) colour.rgba[i] = 255;  // a frame's alpha means nothing here
    return colour;
  }

  std::string FrameName(const FrameKey& key) const override { return Id6(key.scene_id) + "/" + Id6(key.image_id); }

  StatusOr<FrameKey> ParseFrameName(const std::string& name) const override {
    const size_t slash = name.find('/');
    int scene = 0, image = 0;
    if (slash == std::string::npos || !ParseInt(name.substr(0, slash), &scene) ||
        !ParseInt(name.substr(slash + 1), &image))
      return InvalidArgument("'" + name + "' is not a frame name (SCENE/IMAGE)");
    const FrameKey key{scene, image};
    if (!frames_.count(key)) return NotFound("'" + name + "': no such frame in " + split_dir_);
    return key;
  }

  StatusOr<MaskImage> LoadVisibleMask(const FrameKey& key, const GtInstance& gt) const override {
    if (frames_.find(key) == frames_.end()) return MissingFrame(key);
    const std::string scene_dir = SceneDir(key.scene_id);
    const std::string path = scene_dir + "/mask_visib/" + Id6(key.image_id) + "_" + Id6(gt.gt_index) + ".png";
    MCPOSE_ASSIGN_OR_RETURN(MaskImage mask, ReadMaskPng(path));
    const std::string depth_path = scene_dir + "/depth/" + Id6(key.image_id) + ".png";
    MCPOSE_ASSIGN_OR_RETURN(const ImageSize depth, ReadPngSize(depth_path));
    if (mask.width != depth.width || mask.height != depth.height)
      return InvalidArgument(path + ": image is " + std::to_string(mask.width) + "x" + std::to_string(mask.height) +
                             " but the depth image " + depth_path + " of its frame is " + std::to_string(depth.width) +
                             "x" + std::to_string(depth.height));
    return mask;
  }

  std::vector<int> ObjectIds() const override { return object_ids_; }

  std::string ObjectName(int obj_id) const override {
    if (ycbv_ids_ && obj_id >= 1 && obj_id <= static_cast<int>(YcbvClassNames().size())) {
      return YcbvClassNames()[obj_id - 1];
    }
    return "obj_" + Id6(obj_id);
  }

  StatusOr<Mesh> LoadMesh(int obj_id) const override {
    MCPOSE_RETURN_IF_ERROR(CheckObject(obj_id));
    const std::string path = ModelPath(obj_id);
    if (path.ends_with(".obj")) return ReadObjMesh(path);
    return ReadPlyMesh(path, kMmPerMetre);
  }

  // models_dir/obj_NNNNNN.ply; for a dataset of the YCB-Video objects whose models folder is in
  // the YCB-Video layout instead (their textured models, say), models_dir/<name>/textured_simple.obj.
  std::string ModelPath(int obj_id) const override {
    const std::string ply = models_dir_ + "/obj_" + Id6(obj_id) + ".ply";
    if (ycbv_ids_ && obj_id >= 1 && obj_id <= static_cast<int>(YcbvClassNames().size())) {
      std::error_code ec;
      const std::string obj = models_dir_ + "/" + YcbvClassNames()[obj_id - 1] + "/textured_simple.obj";
      if (!fs::exists(ply, ec) && fs::is_regular_file(obj, ec)) return obj;
    }
    return ply;
  }
  const std::string& models_dir() const override { return models_dir_; }

  StatusOr<std::vector<Eigen::Vector3f>> LoadEvalPoints(int obj_id) const override {
    MCPOSE_RETURN_IF_ERROR(CheckObject(obj_id));
    MCPOSE_ASSIGN_OR_RETURN(Mesh mesh, ReadPlyMesh(root_ + "/models/obj_" + Id6(obj_id) + ".ply", kMmPerMetre));
    return std::move(mesh.vertices_m);
  }

 private:
  // Every scene of `frames_` has an entry (filled together in OpenBop).
  const std::string& SceneDir(int scene_id) const { return scene_dirs_.at(scene_id); }

  Status CheckObject(int obj_id) const {
    if (!std::binary_search(object_ids_.begin(), object_ids_.end(), obj_id))
      return NotFound(root_ + "/models/models_info.json: no model with obj_id " + std::to_string(obj_id));
    return Status::Ok();
  }

  // The depth scale of a frame (mm per unit): its scene_camera.json entry's, else camera.json's.
  StatusOr<double> DepthScale(const FrameKey& key) const {
    const std::string camera_path = SceneDir(key.scene_id) + "/scene_camera.json";
    MCPOSE_ASSIGN_OR_RETURN(std::shared_ptr<const SceneCameras> cameras, Cameras(key.scene_id, camera_path));
    const auto cam = cameras->find(key.image_id);
    if (cam == cameras->end()) return NotFound(camera_path + ": no entry for image " + std::to_string(key.image_id));
    const std::optional<double> depth_scale = cam->second.depth_scale ? cam->second.depth_scale : camera_.depth_scale;
    if (!depth_scale) {
      return InvalidArgument(camera_path + ": image " + std::to_string(key.image_id) +
                             ": no depth_scale (and none in " + root_ + "/camera.json)");
    }
    return *depth_scale;
  }

  // The camera of a frame whose depth image (`depth_path`) is width x height: its scene_camera.json
  // cam_K (row-major), checked as a pinhole matrix with the principal point in the image, and the
  // size against camera.json's.
  StatusOr<Intrinsics> Camera(const FrameKey& key, int width, int height, const std::string& depth_path) const {
    const std::string camera_path = SceneDir(key.scene_id) + "/scene_camera.json";
    MCPOSE_ASSIGN_OR_RETURN(std::shared_ptr<const SceneCameras> cameras, Cameras(key.scene_id, camera_path));
    const auto cam = cameras->find(key.image_id);
    if (cam == cameras->end()) return NotFound(camera_path + ": no entry for image " + std::to_string(key.image_id));
    if (camera_.width > 0 && (width != camera_.width || height != camera_.height)) {
      return InvalidArgument(depth_path + ": depth image is " + std::to_string(width) + "x" + std::to_string(height) +
                             " but " + root_ + "/camera.json says " + std::to_string(camera_.width) + "x" +
                             std::to_string(camera_.height));
    }
    const double* K = cam->second.K;
    const std::string where = camera_path + ": image " + std::to_string(key.image_id) + ": cam_K: ";
    if (const std::string problem = limits::CheckPinholeMatrix(K, width, height); !problem.empty())
      return InvalidArgument(where + problem + " (depth image " + depth_path + ")");
    return Intrinsics{K[0], K[4], K[2], K[5], width, height};
  }

  Status MissingFrame(const FrameKey& key) const {
    return NotFound(split_dir_ + ": no ground truth for scene " + std::to_string(key.scene_id) +
                    " image " + std::to_string(key.image_id));
  }

  // scene_camera.json of one scene, parsed once and shared between threads.
  StatusOr<std::shared_ptr<const SceneCameras>> Cameras(int scene_id, const std::string& path) const {
    {
      std::lock_guard<std::mutex> lock(cameras_mutex_);
      const auto it = cameras_.find(scene_id);
      if (it != cameras_.end()) return it->second;
    }
    MCPOSE_ASSIGN_OR_RETURN(SceneCameras parsed, ParseSceneCamera(path));
    auto shared = std::make_shared<const SceneCameras>(std::move(parsed));
    std::lock_guard<std::mutex> lock(cameras_mutex_);
    cameras_.emplace(scene_id, shared);
    return shared;
  }

  std::string root_;
  std::string split_dir_;
  std::string models_dir_;
  std::vector<int> object_ids_;  // sorted
  bool ycbv_ids_ = false;
  DatasetCamera camera_;
  std::map<int, std::string> scene_dirs_;  // scene_id -> <split>/<scene folder>
  std::map<FrameKey, std::vector<GtInstance>> frames_;
  mutable std::mutex cameras_mutex_;
  mutable std::map<int, std::shared_ptr<const SceneCameras>> cameras_;
};

StatusOr<std::unique_ptr<Dataset>> OpenBop(const std::string& root, const std::string& split,
                                           const std::string& models_dir) {
  // Objects: the keys of models_info.json.
  const std::string info_path = root + "/models/models_info.json";
  MCPOSE_ASSIGN_OR_RETURN(json info, ReadJsonFile(info_path));
  if (!info.is_object() || info.empty()) {
    return InvalidArgument(info_path + ": expected a non-empty object keyed by obj_id");
  }
  std::vector<int> object_ids;
  for (const auto& [key, value] : info.items()) {
    int obj_id = 0;
    if (!IsIdKey(key) || !ParseInt(key, &obj_id) || obj_id < 1) {
      return InvalidArgument(info_path + ": key '" + key + "' is not a positive obj_id (digits, no leading zero)");
    }
    const std::string model = root + "/models/obj_" + Id6(obj_id) + ".ply";
    std::error_code exists_ec;
    if (!fs::is_regular_file(model, exists_ec)) {
      return InvalidArgument(info_path + ": key '" + key + "' names no model file (" + model + " does not exist)");
    }
    object_ids.push_back(obj_id);
  }
  std::sort(object_ids.begin(), object_ids.end());

  MCPOSE_ASSIGN_OR_RETURN(DatasetCamera camera, ParseDatasetCamera(root + "/camera.json"));

  // Frames: every image of every scene_gt.json of the split.
  const std::string split_dir = root + "/" + split;
  std::map<FrameKey, std::vector<GtInstance>> frames;
  std::error_code ec;
  std::vector<fs::path> scene_dirs;
  for (fs::directory_iterator it(split_dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (AllDigits(it->path().filename().string()) && it->is_directory(ec)) {
      scene_dirs.push_back(it->path());
    }
  }
  if (ec) return DataLoss(split_dir + ": cannot list folder (" + ec.message() + ")");
  std::sort(scene_dirs.begin(), scene_dirs.end());
  std::map<int, std::string> scenes;
  for (const fs::path& dir : scene_dirs) {
    const std::string gt_path = (dir / "scene_gt.json").string();
    if (!fs::exists(gt_path, ec)) continue;
    const int scene_id = std::stoi(dir.filename().string());
    if (!scenes.emplace(scene_id, dir.string()).second) {
      return InvalidArgument(dir.string() + ": a second folder for scene " +
                             std::to_string(scene_id) + " (besides " + scenes[scene_id] + ")");
    }
    MCPOSE_RETURN_IF_ERROR(ParseSceneGt(gt_path, scene_id, &frames));
  }
  if (scenes.empty()) {
    return NotFound(split_dir + ": no scene folder with a scene_gt.json");
  }
  return std::unique_ptr<Dataset>(new BopDataset(root, split, models_dir, std::move(object_ids), camera,
                                                 std::move(scenes), std::move(frames)));
}

}  // namespace

StatusOr<std::unique_ptr<Dataset>> OpenBopDataset(const std::string& root, const std::string& split,
                                                  const std::string& models_dir) {
  try {
    return OpenBop(root, split, models_dir);
  } catch (const std::exception& e) {
    return Internal(root + ": cannot open BOP dataset (" + e.what() + ")");
  }
}

}  // namespace mcpose::io

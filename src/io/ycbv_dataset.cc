#include "io/ycbv_dataset.h"

#include <matio.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <map>

#include "mcpose/limits.h"
#include "mcpose/io_util.h"
#include "io/obj_io.h"
#include "mcpose/png_io.h"

namespace mcpose::io {
namespace {

namespace fs = std::filesystem;

// A numeric MATLAB array converted to double, column-major, with its dimensions.
struct MatArray {
  std::vector<size_t> dims;
  std::vector<double> values;
};

template <typename T>
void ConvertAll(const void* data, size_t n, std::vector<double>* out) {
  const T* p = static_cast<const T*>(data);
  out->resize(n);
  for (size_t i = 0; i < n; ++i) (*out)[i] = static_cast<double>(p[i]);
}

std::string DimsString(const std::vector<size_t>& dims) {
  std::string s;
  for (size_t i = 0; i < dims.size(); ++i) {
    if (i) s += 'x';
    s += std::to_string(dims[i]);
  }
  return s;
}

// The element count of `dims`, or 0 if it exceeds limits::kMaxMatElements (or overflows).
size_t BoundedElementCount(const size_t* dims, int rank) {
  size_t n = 1;
  for (int i = 0; i < rank; ++i) {
    if (dims[i] != 0 && n > limits::kMaxMatElements / dims[i]) return 0;
    n *= dims[i];
  }
  return n <= limits::kMaxMatElements ? n : 0;
}

// Reads variable `name` of any real numeric class. Its header is read first and its size
// checked against limits::kMaxMatElements and the file size, so a header that lies cannot make
// libmatio allocate for it. Errors name `path` and `name`.
StatusOr<MatArray> ReadMatArray(mat_t* mat, const std::string& path, size_t file_bytes, const char* name) {
  matvar_t* info = Mat_VarReadInfo(mat, name);
  if (!info) return InvalidArgument(path + ": variable '" + name + "' is missing or unreadable");
  const size_t claimed = info->rank > 0 && info->dims ? BoundedElementCount(info->dims, info->rank) : 0;
  const size_t claimed_dims_rank = static_cast<size_t>(std::max(info->rank, 0));
  std::vector<size_t> claimed_dims(info->dims, info->dims + (info->dims ? claimed_dims_rank : 0));
  const bool compressed = info->compression != MAT_COMPRESSION_NONE;
  const size_t claimed_element_bytes = Mat_SizeOfClass(info->class_type);
  Mat_VarFree(info);
  // Uncompressed data must fit in the file; zlib inflates at most about 1032:1.
  const double max_bytes = (compressed ? 1032.0 : 1.0) * static_cast<double>(file_bytes);
  if (claimed == 0 && !claimed_dims.empty() &&
      std::none_of(claimed_dims.begin(), claimed_dims.end(), [](size_t d) { return d == 0; })) {
    return InvalidArgument(path + ": variable '" + name + "' claims " + DimsString(claimed_dims) +
                           " elements, more than the limit of " + std::to_string(limits::kMaxMatElements));
  }
  if (static_cast<double>(claimed) * static_cast<double>(claimed_element_bytes) > max_bytes) {
    return InvalidArgument(path + ": variable '" + name + "' claims " + DimsString(claimed_dims) +
                           " elements, more than the file's " + std::to_string(file_bytes) + " bytes hold");
  }
  matvar_t* var = Mat_VarRead(mat, name);
  if (!var) return InvalidArgument(path + ": variable '" + name + "' is missing or unreadable");
  if (var->rank <= 0 || !var->dims || BoundedElementCount(var->dims, var->rank) != claimed) {
    Mat_VarFree(var);
    return InvalidArgument(path + ": variable '" + name + "' changed size between its header and its data");
  }
  MatArray array;
  array.dims.assign(var->dims, var->dims + var->rank);
  size_t n = 1;
  for (size_t d : array.dims) n *= d;
  const bool complex_or_sparse = var->isComplex || var->class_type == MAT_C_SPARSE;
  const size_t element_bytes = Mat_SizeOfClass(var->class_type);
  const bool enough_data = var->data && element_bytes > 0 && var->nbytes >= n * element_bytes;
  bool numeric = !complex_or_sparse && enough_data;
  if (numeric) {
    switch (var->class_type) {
      case MAT_C_DOUBLE: ConvertAll<double>(var->data, n, &array.values); break;
      case MAT_C_SINGLE: ConvertAll<float>(var->data, n, &array.values); break;
      case MAT_C_INT8: ConvertAll<int8_t>(var->data, n, &array.values); break;
      case MAT_C_UINT8: ConvertAll<uint8_t>(var->data, n, &array.values); break;
      case MAT_C_INT16: ConvertAll<int16_t>(var->data, n, &array.values); break;
      case MAT_C_UINT16: ConvertAll<uint16_t>(var->data, n, &array.values); break;
      case MAT_C_INT32: ConvertAll<int32_t>(var->data, n, &array.values); break;
      case MAT_C_UINT32: ConvertAll<uint32_t>(var->data, n, &array.values); break;
      case MAT_C_INT64: ConvertAll<int64_t>(var->data, n, &array.values); break;
      case MAT_C_UINT64: ConvertAll<uint64_t>(var->data, n, &array.values); break;
      default: numeric = false;
    }
  }
  const int class_type = static_cast<int>(var->class_type);
  Mat_VarFree(var);
  if (!numeric) {
    return InvalidArgument(path + ": variable '" + name + "' is not a real numeric array (class " +
                           std::to_string(class_type) + ")");
  }
  for (size_t i = 0; i < n; ++i) {
    if (!std::isfinite(array.values[i])) {
      return InvalidArgument(path + ": variable '" + name + "' has a non-finite value at index " +
                             std::to_string(i));
    }
  }
  return array;
}

// MATLAB dimensions without trailing singleton dimensions beyond the second.
std::vector<size_t> Squeeze(std::vector<size_t> dims) {
  while (dims.size() > 2 && dims.back() == 1) dims.pop_back();
  return dims;
}

StatusOr<YcbvMeta> ReadMetaFromOpenFile(mat_t* mat, const std::string& path, size_t file_bytes) {
  YcbvMeta meta;

  // intrinsic_matrix: 3x3, column-major in the file.
  MCPOSE_ASSIGN_OR_RETURN(MatArray K, ReadMatArray(mat, path, file_bytes, "intrinsic_matrix"));
  if (Squeeze(K.dims) != std::vector<size_t>{3, 3}) {
    return InvalidArgument(path + ": intrinsic_matrix must be 3x3, got " + DimsString(K.dims));
  }
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) meta.K(r, c) = K.values[r + 3 * c];
  }
  for (const auto& [field, f] : {std::pair{"fx", meta.K(0, 0)}, std::pair{"fy", meta.K(1, 1)}}) {
    if (const std::string problem = limits::CheckFocal(field, f); !problem.empty())
      return InvalidArgument(path + ": intrinsic_matrix: " + problem);
  }
  for (const auto& [field, c] : {std::pair{"cx", meta.K(0, 2)}, std::pair{"cy", meta.K(1, 2)}}) {
    if (!(c >= 0 && c <= limits::kMaxImageSide))
      return InvalidArgument(path + ": intrinsic_matrix: " + field + " = " + limits::Num(c) + " px is outside 0-" +
                             std::to_string(limits::kMaxImageSide) + " px");
  }

  // factor_depth: one positive number (uint16 in real frames, double in synthetic ones).
  MCPOSE_ASSIGN_OR_RETURN(MatArray factor, ReadMatArray(mat, path, file_bytes, "factor_depth"));
  if (factor.values.size() != 1 || !(factor.values[0] > 0)) {
    return InvalidArgument(path + ": factor_depth must be one positive number, got " +
                           (factor.values.size() == 1 ? std::to_string(factor.values[0])
                                                      : DimsString(factor.dims) + " values"));
  }
  meta.factor_depth = factor.values[0];
  if (const std::string problem = limits::CheckDepthScale(1.0 / meta.factor_depth); !problem.empty())
    return InvalidArgument(path + ": factor_depth = " + limits::Num(meta.factor_depth) + ": " + problem);

  // cls_indexes: N positive integers (uint8 Nx1 or single 1xN).
  MCPOSE_ASSIGN_OR_RETURN(MatArray cls, ReadMatArray(mat, path, file_bytes, "cls_indexes"));
  const std::vector<size_t> cls_dims = Squeeze(cls.dims);
  if (cls_dims.size() != 2 || std::min(cls_dims[0], cls_dims[1]) != 1) {
    return InvalidArgument(path + ": cls_indexes must be a vector, got " + DimsString(cls.dims));
  }
  for (size_t i = 0; i < cls.values.size(); ++i) {
    const double v = cls.values[i];
    if (v < 1 || v != std::floor(v) || v > 1e6) {
      return InvalidArgument(path + ": cls_indexes[" + std::to_string(i) +
                             "] = " + std::to_string(v) + " is not a positive integer");
    }
    meta.cls_indexes.push_back(static_cast<int>(v));
  }
  const size_t n = meta.cls_indexes.size();

  // poses: 3x4xN, or 3x4 when N = 1; column-major, element (r, c, k) at r + 3 c + 12 k.
  MCPOSE_ASSIGN_OR_RETURN(MatArray poses, ReadMatArray(mat, path, file_bytes, "poses"));
  const std::vector<size_t> pose_dims = Squeeze(poses.dims);
  const bool shape_ok = pose_dims.size() >= 2 && pose_dims.size() <= 3 && pose_dims[0] == 3 &&
                        pose_dims[1] == 4 && (pose_dims.size() == 3 ? pose_dims[2] : 1) == n;
  if (!shape_ok) {
    return InvalidArgument(path + ": poses must be 3x4x" + std::to_string(n) +
                           " (one per cls_indexes entry), got " + DimsString(poses.dims));
  }
  for (size_t k = 0; k < n; ++k) {
    SE3 T;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) T.R(r, c) = poses.values[r + 3 * c + 12 * k];
      T.t(r) = poses.values[r + 3 * 3 + 12 * k];
    }
    const std::string where = path + ": poses[:, :, " + std::to_string(k) + "] (cls_indexes " +
                              std::to_string(meta.cls_indexes[k]) + "): ";
    if (const std::string problem = limits::CheckRotation(T.R); !problem.empty())
      return InvalidArgument(where + problem);
    if (const std::string problem = limits::CheckCoordinates(T.t); !problem.empty())
      return InvalidArgument(where + "translation " + problem);
    meta.poses.push_back(T);
  }
  return meta;
}

// Ok if the image at `path` has the size of the depth image at `depth_path`.
Status CheckSameSize(const std::string& path, ImageSize size, const std::string& depth_path, int width, int height) {
  if (size.width == width && size.height == height) return Status::Ok();
  return InvalidArgument(path + ": image is " + std::to_string(size.width) + "x" + std::to_string(size.height) +
                         " but the depth image " + depth_path + " of its frame is " + std::to_string(width) + "x" +
                         std::to_string(height));
}

std::string ObjName(int obj_id) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "obj_%06d", obj_id);
  return buffer;
}

bool AllDigits(const std::string& s, size_t n) {
  return s.size() == n && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// The intrinsics of a frame whose depth image (`depth_path`) is width x height: a pinhole K (zero
// skew, last row 0 0 1) with the principal point in the image, from its meta.mat.
StatusOr<Intrinsics> CheckedIntrinsics(const std::string& meta_path, const YcbvMeta& meta, int width, int height,
                                       const std::string& depth_path) {
  const Eigen::Matrix3d& K = meta.K;
  const double rows[9] = {K(0, 0), K(0, 1), K(0, 2), K(1, 0), K(1, 1), K(1, 2), K(2, 0), K(2, 1), K(2, 2)};
  if (const std::string problem = limits::CheckPinholeMatrix(rows, width, height); !problem.empty())
    return InvalidArgument(meta_path + ": intrinsic_matrix: " + problem + " (depth image " + depth_path + ")");
  return Intrinsics{K(0, 0), K(1, 1), K(0, 2), K(1, 2), width, height};
}

class YcbvDataset final : public Dataset {
 public:
  YcbvDataset(std::string root, std::string models_dir, std::vector<std::string> class_names,
              std::map<FrameKey, std::string> frame_prefixes, std::vector<int> object_ids)
      : root_(std::move(root)),
        models_dir_(std::move(models_dir)),
        class_names_(std::move(class_names)),
        frame_prefixes_(std::move(frame_prefixes)),
        object_ids_(std::move(object_ids)) {}

  DatasetFormat format() const override { return DatasetFormat::kYcbv; }
  const std::string& root() const override { return root_; }

  std::vector<FrameKey> Frames() const override {
    std::vector<FrameKey> keys;
    keys.reserve(frame_prefixes_.size());
    for (const auto& [key, prefix] : frame_prefixes_)
      if (key.scene_id != kSyntheticScene) keys.push_back(key);
    return keys;
  }

  StatusOr<ColourImage> LoadColour(const Frame& frame) const override {
    MCPOSE_ASSIGN_OR_RETURN(const std::string prefix, Prefix(frame.key));
    const std::string path = prefix + "-color.png";
    MCPOSE_ASSIGN_OR_RETURN(ColourImage colour, ReadColourPng(path));
    if (colour.width != frame.depth.width || colour.height != frame.depth.height)
      return InvalidArgument(path + ": colour image is " + std::to_string(colour.width) + "x" +
                             std::to_string(colour.height) + " but the depth image " + frame.depth_path + " is " +
                             std::to_string(frame.depth.width) + "x" + std::to_string(frame.depth.height));
    for (size_t i = 3; i < colour.rgba.size(); i += 4) colour.rgba[i] = 255;  // a frame's alpha means nothing here
    return colour;
  }

  std::string FrameName(const FrameKey& key) const override {
    char buffer[48];
    if (key.scene_id == kSyntheticScene) {
      std::snprintf(buffer, sizeof buffer, "data_syn/%06d", key.image_id);
    } else {
      std::snprintf(buffer, sizeof buffer, "%04d/%06d", key.scene_id, key.image_id);
    }
    return buffer;
  }

  StatusOr<FrameKey> ParseFrameName(const std::string& name) const override {
    const size_t slash = name.find('/');
    int scene = 0, image = 0;
    const std::string head = name.substr(0, slash == std::string::npos ? 0 : slash);
    const bool ok = slash != std::string::npos && ParseInt(name.substr(slash + 1), &image) &&
                    (head == "data_syn" ? (scene = kSyntheticScene, true) : ParseInt(head, &scene));
    if (!ok) return InvalidArgument("'" + name + "' is not a frame name (VIDEO/FRAME or data_syn/FRAME)");
    const FrameKey key{scene, image};
    if (!frame_prefixes_.count(key)) return NotFound("'" + name + "': no such frame in " + root_);
    return key;
  }

  StatusOr<Intrinsics> LoadIntrinsics(const FrameKey& key) const override {
    MCPOSE_ASSIGN_OR_RETURN(const std::string prefix, Prefix(key));
    const std::string meta_path = prefix + "-meta.mat";
    MCPOSE_ASSIGN_OR_RETURN(YcbvMeta meta, ReadYcbvMeta(meta_path));
    const std::string depth_path = prefix + "-depth.png";
    MCPOSE_ASSIGN_OR_RETURN(const ImageSize size, ReadPngSize(depth_path));
    return CheckedIntrinsics(meta_path, meta, size.width, size.height, depth_path);
  }

  StatusOr<Frame> LoadFrame(const FrameKey& key) const override {
    MCPOSE_ASSIGN_OR_RETURN(const std::string prefix, Prefix(key));
    const std::string meta_path = prefix + "-meta.mat";
    MCPOSE_ASSIGN_OR_RETURN(YcbvMeta meta, ReadYcbvMeta(meta_path));

    // Depth in metres; the PNG gives the image size.
    std::error_code ec;
    Frame frame;
    frame.key = key;
    frame.depth_path = prefix + "-depth.png";
    MCPOSE_ASSIGN_OR_RETURN(frame.depth, ReadDepthPng(frame.depth_path, 1.0 / meta.factor_depth));

    MCPOSE_ASSIGN_OR_RETURN(frame.K,
                            CheckedIntrinsics(meta_path, meta, frame.depth.width, frame.depth.height, frame.depth_path));

    // The colour and label images of the frame, where present, must have the depth's size.
    for (const char* suffix : {"-color.png", "-label.png"}) {
      const std::string path = prefix + suffix;
      if (!fs::exists(path, ec)) continue;
      MCPOSE_ASSIGN_OR_RETURN(const ImageSize size, ReadPngSize(path));
      MCPOSE_RETURN_IF_ERROR(CheckSameSize(path, size, frame.depth_path, frame.depth.width, frame.depth.height));
    }

    // Ground truth in meta.mat order.
    for (size_t i = 0; i < meta.poses.size(); ++i) {
      const int obj_id = meta.cls_indexes[i];
      if (obj_id > static_cast<int>(class_names_.size())) {
        return InvalidArgument(meta_path + ": cls_indexes[" + std::to_string(i) + "] = " +
                               std::to_string(obj_id) + " is not a class of classes.txt (" +
                               std::to_string(class_names_.size()) + " classes)");
      }
      frame.gt.push_back({obj_id, static_cast<int>(i), meta.poses[i]});
    }
    return frame;
  }

  StatusOr<MaskImage> LoadVisibleMask(const FrameKey& key, const GtInstance& gt) const override {
    MCPOSE_ASSIGN_OR_RETURN(const std::string prefix, Prefix(key));
    const std::string label_path = prefix + "-label.png";
    if (gt.obj_id < 1 || gt.obj_id > 255) {
      return InvalidArgument(label_path + ": obj_id " + std::to_string(gt.obj_id) +
                             " cannot appear in an 8-bit label image");
    }
    MCPOSE_ASSIGN_OR_RETURN(MaskImage mask, ReadMaskPng(label_path));
    const std::string depth_path = prefix + "-depth.png";
    MCPOSE_ASSIGN_OR_RETURN(const ImageSize depth_size, ReadPngSize(depth_path));
    MCPOSE_RETURN_IF_ERROR(
        CheckSameSize(label_path, {mask.width, mask.height}, depth_path, depth_size.width, depth_size.height));
    for (uint8_t& v : mask.values) v = (v == gt.obj_id) ? 255 : 0;
    return mask;
  }

  std::vector<int> ObjectIds() const override { return object_ids_; }

  std::string ObjectName(int obj_id) const override {
    if (obj_id >= 1 && obj_id <= static_cast<int>(class_names_.size())) {
      return class_names_[obj_id - 1];
    }
    return ObjName(obj_id);
  }

  StatusOr<Mesh> LoadMesh(int obj_id) const override {
    MCPOSE_RETURN_IF_ERROR(CheckObject(obj_id));
    return ReadObjMesh(ModelPath(obj_id) + "/textured_simple.obj");
  }

  std::string ModelPath(int obj_id) const override { return models_dir_ + "/" + ObjectName(obj_id); }
  const std::string& models_dir() const override { return models_dir_; }

  StatusOr<std::vector<Eigen::Vector3f>> LoadEvalPoints(int obj_id) const override {
    MCPOSE_RETURN_IF_ERROR(CheckObject(obj_id));
    return ReadXyzPoints(root_ + "/models/" + ObjectName(obj_id) + "/points.xyz");
  }

 private:
  StatusOr<std::string> Prefix(const FrameKey& key) const {
    const auto it = frame_prefixes_.find(key);
    if (it == frame_prefixes_.end()) {
      return NotFound(root_ + ": no frame with scene_id " + std::to_string(key.scene_id) +
                      " and image_id " + std::to_string(key.image_id) + " in data/");
    }
    return it->second;
  }

  Status CheckObject(int obj_id) const {
    if (!std::binary_search(object_ids_.begin(), object_ids_.end(), obj_id)) {
      return NotFound(root_ + ": no model with obj_id " + std::to_string(obj_id) +
                      " (classes.txt lists " + std::to_string(class_names_.size()) +
                      " classes; models/<name>/textured_simple.obj must exist)");
    }
    return Status::Ok();
  }

  std::string root_;
  std::string models_dir_;
  std::vector<std::string> class_names_;             // element k - 1: obj_id k
  std::map<FrameKey, std::string> frame_prefixes_;   // ".../data/0049/000001", ".../data_syn/000001"
  std::vector<int> object_ids_;                      // sorted; classes with a mesh file
};

// classes.txt: one name per line; line k is obj_id k. Trailing empty lines are allowed.
StatusOr<std::vector<std::string>> ReadClassNames(const std::string& path) {
  MCPOSE_ASSIGN_OR_RETURN(std::string text, ReadFileToString(path));
  std::vector<std::string> names;
  for (std::string_view line : SplitLines(text)) names.emplace_back(Trim(line));
  while (!names.empty() && names.back().empty()) names.pop_back();
  if (names.empty()) return InvalidArgument(path + ": no class names");
  for (size_t i = 0; i < names.size(); ++i) {
    if (names[i].empty() || names[i].find_first_of("/\\") != std::string::npos) {
      return InvalidArgument(path + ": line " + std::to_string(i + 1) +
                             ": expected a class name, got '" + names[i] + "'");
    }
  }
  return names;
}

StatusOr<std::unique_ptr<Dataset>> OpenYcbv(const std::string& root, const std::string& models_dir) {
  MCPOSE_ASSIGN_OR_RETURN(std::vector<std::string> names, ReadClassNames(root + "/classes.txt"));

  // Objects: the classes whose mesh is present.
  std::vector<int> object_ids;
  std::error_code ec;
  for (size_t i = 0; i < names.size(); ++i) {
    if (fs::is_regular_file(root + "/models/" + names[i] + "/textured_simple.obj", ec)) {
      object_ids.push_back(static_cast<int>(i + 1));
    }
  }

  // Frames: data/<4-digit video>/<6-digit frame>-meta.mat.
  std::map<FrameKey, std::string> frames;
  const std::string data_dir = root + "/data";
  for (fs::directory_iterator video(data_dir, ec), end; !ec && video != end; video.increment(ec)) {
    const std::string video_name = video->path().filename().string();
    if (!AllDigits(video_name, 4) || !video->is_directory(ec)) continue;
    std::error_code frame_ec;
    for (fs::directory_iterator file(video->path(), frame_ec); !frame_ec && file != end;
         file.increment(frame_ec)) {
      const std::string name = file->path().filename().string();
      constexpr std::string_view kSuffix = "-meta.mat";
      if (name.size() != 6 + kSuffix.size() || !name.ends_with(kSuffix)) continue;
      const std::string frame_name = name.substr(0, 6);
      if (!AllDigits(frame_name, 6)) continue;
      const FrameKey key{std::stoi(video_name), std::stoi(frame_name)};
      frames[key] = data_dir + "/" + video_name + "/" + frame_name;
    }
    if (frame_ec) {
      return DataLoss(video->path().string() + ": cannot list folder (" + frame_ec.message() + ")");
    }
  }
  if (ec) return DataLoss(data_dir + ": cannot list folder (" + ec.message() + ")");
  // Synthetic frames: data_syn/<6-digit frame>-meta.mat, if the folder exists.
  const std::string syn_dir = root + "/data_syn";
  std::error_code syn_ec;
  for (fs::directory_iterator file(syn_dir, syn_ec), end; !syn_ec && file != end; file.increment(syn_ec)) {
    const std::string name = file->path().filename().string();
    if (name.size() != 15 || !name.ends_with("-meta.mat") || !AllDigits(name.substr(0, 6), 6)) continue;
    frames[FrameKey{kSyntheticScene, std::stoi(name.substr(0, 6))}] = syn_dir + "/" + name.substr(0, 6);
  }
  return std::unique_ptr<Dataset>(
      new YcbvDataset(root, models_dir, std::move(names), std::move(frames), std::move(object_ids)));
}

// MAT5 data types of the element tags this check reads.
constexpr uint32_t kMiInt32 = 5, kMiUint32 = 6, kMiMatrix = 14, kMiCompressed = 15;

uint32_t Mat5Word(const unsigned char* p, bool swap) {
  uint32_t v;
  std::memcpy(&v, p, 4);
  return swap ? __builtin_bswap32(v) : v;
}

// Checks the header of one miMATRIX element (`data`, `size` bytes: its array flags, dimensions
// and name sub-elements) before libmatio reads it: libmatio allocates the dimensions and the
// name as their tags claim, so a tag that lies would make it allocate gigabytes.
std::string CheckMat5MatrixHeader(const unsigned char* data, size_t size, bool swap) {
  size_t at = 0;
  for (int sub = 0; sub < 3 && at + 8 <= size; ++sub) {
    const uint32_t tag = Mat5Word(data + at, swap);
    if (tag >> 16) {  // small data element: 4 bytes of data in the tag
      at += 8;
      continue;
    }
    const uint32_t bytes = Mat5Word(data + at + 4, swap);
    // Flags: 8 bytes; dimensions: at most 32 of them; name: at most 64 characters.
    const uint32_t most = sub == 0 ? 8 : sub == 1 ? 32 * 4 : 64;
    if (bytes > most || (sub == 0 && tag != kMiUint32) || (sub == 1 && tag != kMiInt32))
      return "a variable's " + std::string(sub == 0 ? "array flags" : sub == 1 ? "dimensions" : "name") +
             " claim " + std::to_string(bytes) + " bytes (type " + std::to_string(tag) + "), more than a MAT-file variable has";
    at += 8 + ((bytes + 7u) & ~7u);
  }
  return {};
}

// Walks the top-level elements of a MATLAB 5 file (`bytes`, header included): each must fit in
// the file, and each variable's header (inflated where compressed) must claim sane sizes.
std::string CheckMat5Elements(const std::string& bytes) {
  const bool swap = bytes.compare(126, 2, "MI") == 0;
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  size_t at = 128;
  while (at + 8 <= bytes.size()) {
    const uint32_t tag = Mat5Word(data + at, swap);
    if (tag >> 16) {
      at += 8;
      continue;
    }
    const uint64_t size = Mat5Word(data + at + 4, swap);
    if (size > bytes.size() - at - 8)
      return "the element at byte " + std::to_string(at) + " claims " + std::to_string(size) + " bytes, more than the " +
             std::to_string(bytes.size() - at - 8) + " left in the file";
    const unsigned char* body = data + at + 8;
    std::string problem;
    if (tag == kMiMatrix) {
      problem = CheckMat5MatrixHeader(body, static_cast<size_t>(size), swap);
    } else if (tag == kMiCompressed) {
      // The first bytes of the inflated variable: its miMATRIX tag and header sub-elements.
      unsigned char head[8 + 16 + 8 + 32 * 4 + 8 + 64];
      z_stream z{};
      if (inflateInit(&z) != Z_OK) return "zlib could not start";
      z.next_in = const_cast<unsigned char*>(body);
      z.avail_in = static_cast<uInt>(size);
      z.next_out = head;
      z.avail_out = sizeof head;
      const int rc = inflate(&z, Z_SYNC_FLUSH);
      const size_t got = sizeof head - z.avail_out;
      inflateEnd(&z);
      if (rc != Z_OK && rc != Z_STREAM_END && rc != Z_BUF_ERROR)
        return "the compressed element at byte " + std::to_string(at) + " does not inflate";
      if (got >= 8 && Mat5Word(head, swap) == kMiMatrix) problem = CheckMat5MatrixHeader(head + 8, got - 8, swap);
    }
    if (!problem.empty()) return "the element at byte " + std::to_string(at) + ": " + problem;
    at += 8 + (tag == kMiCompressed ? size : (size + 7u) & ~uint64_t{7});
  }
  return {};
}

}  // namespace

StatusOr<YcbvMeta> ReadYcbvMeta(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) return NotFound(path + ": file does not exist");
  // Only MATLAB 5 files: a 128-byte header ending in version 0x0100 and the "IM"/"MI" endian
  // mark. Other formats (v7.3 is HDF5) are not opened at all.
  MCPOSE_ASSIGN_OR_RETURN(const std::string bytes, ReadFileToString(path));
  constexpr size_t kMat5HeaderBytes = 128;
  const bool mat5 = bytes.size() > kMat5HeaderBytes &&
                    ((bytes.compare(124, 4, std::string("\x00\x01IM", 4)) == 0) ||
                     (bytes.compare(124, 4, std::string("\x01\x00MI", 4)) == 0));
  if (!mat5) return DataLoss(path + ": not a MATLAB 5 MAT-file (header of " + std::to_string(bytes.size()) + " bytes)");
  if (const std::string problem = CheckMat5Elements(bytes); !problem.empty()) return DataLoss(path + ": " + problem);
  mat_t* mat = Mat_Open(path.c_str(), MAT_ACC_RDONLY);
  if (!mat) return DataLoss(path + ": not a readable MATLAB MAT-file");
  StatusOr<YcbvMeta> meta = InvalidArgument(path + ": not read");
  try {
    meta = ReadMetaFromOpenFile(mat, path, bytes.size());
  } catch (const std::exception& e) {
    meta = Internal(path + ": MAT-file read failed (" + e.what() + ")");
  }
  Mat_Close(mat);
  return meta;
}

Status WriteYcbvMeta(const std::string& path, const YcbvMeta& meta) {
  const size_t n = meta.cls_indexes.size();
  if (meta.poses.size() != n) {
    return InvalidArgument(path + ": " + std::to_string(meta.poses.size()) + " poses for " +
                           std::to_string(n) + " cls_indexes");
  }
  // Column-major arrays, as MATLAB stores them.
  std::vector<double> K(9), poses(12 * n);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) K[r + 3 * c] = meta.K(r, c);
  }
  for (size_t k = 0; k < n; ++k) {
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) poses[r + 3 * c + 12 * k] = meta.poses[k].R(r, c);
      poses[r + 9 + 12 * k] = meta.poses[k].t(r);
    }
  }
  std::vector<uint8_t> cls(n);
  for (size_t k = 0; k < n; ++k) {
    if (meta.cls_indexes[k] < 0 || meta.cls_indexes[k] > 255) {
      return InvalidArgument(path + ": cls_indexes[" + std::to_string(k) + "] does not fit uint8");
    }
    cls[k] = static_cast<uint8_t>(meta.cls_indexes[k]);
  }
  double factor = meta.factor_depth;

  // libmatio writes to a file of its own; its bytes then go to `path` through WriteFileAtomic,
  // as every output (flushed to disk, renamed into place).
  const std::string tmp = path + ".matio.tmp";
  mat_t* mat = Mat_CreateVer(tmp.c_str(), nullptr, MAT_FT_MAT5);
  if (!mat) return NotFound(tmp + ": cannot create MAT-file");
  struct Variable {
    const char* name;
    matio_classes class_type;
    matio_types data_type;
    std::vector<size_t> dims;
    void* data;
  } variables[] = {
      {"intrinsic_matrix", MAT_C_DOUBLE, MAT_T_DOUBLE, {3, 3}, K.data()},
      {"factor_depth", MAT_C_DOUBLE, MAT_T_DOUBLE, {1, 1}, &factor},
      {"poses", MAT_C_DOUBLE, MAT_T_DOUBLE, {3, 4, n}, poses.data()},
      {"cls_indexes", MAT_C_UINT8, MAT_T_UINT8, {n, 1}, cls.data()},
  };
  bool ok = true;
  for (Variable& v : variables) {
    matvar_t* var = Mat_VarCreate(v.name, v.class_type, v.data_type, static_cast<int>(v.dims.size()),
                                  v.dims.data(), v.data, 0);
    ok = ok && var && Mat_VarWrite(mat, var, MAT_COMPRESSION_NONE) == 0;
    if (var) Mat_VarFree(var);
  }
  ok = Mat_Close(mat) == 0 && ok;
  std::error_code ec;
  if (!ok) {
    fs::remove(tmp, ec);
    return Internal(path + ": MAT-file write failed");
  }
  StatusOr<std::string> bytes = ReadFileToString(tmp);
  fs::remove(tmp, ec);
  if (!bytes.ok()) return bytes.status();
  return WriteFileAtomic(path, *bytes);
}

StatusOr<std::vector<Eigen::Vector3f>> ReadXyzPoints(const std::string& path) {
  MCPOSE_ASSIGN_OR_RETURN(std::string text, ReadFileToString(path));
  std::vector<Eigen::Vector3f> points;
  const std::vector<std::string_view> lines = SplitLines(text);
  for (size_t i = 0; i < lines.size(); ++i) {
    const std::vector<std::string_view> tokens = SplitWhitespace(lines[i]);
    if (tokens.empty()) continue;
    double xyz[3];
    if (tokens.size() < 3 || !ParseDouble(tokens[0], &xyz[0]) || !ParseDouble(tokens[1], &xyz[1]) ||
        !ParseDouble(tokens[2], &xyz[2]) || !std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) ||
        !std::isfinite(xyz[2])) {
      return InvalidArgument(path + ": line " + std::to_string(i + 1) +
                             ": expected 'x y z' (finite numbers), got '" +
                             std::string(Trim(lines[i])) + "'");
    }
    if (const std::string problem = limits::CheckCoordinates(Eigen::Vector3d(xyz[0], xyz[1], xyz[2]));
        !problem.empty()) {
      return InvalidArgument(path + ": line " + std::to_string(i + 1) + ": " + problem);
    }
    points.emplace_back(static_cast<float>(xyz[0]), static_cast<float>(xyz[1]),
                        static_cast<float>(xyz[2]));
  }
  if (points.empty()) return InvalidArgument(path + ": no points");
  return points;
}

StatusOr<std::unique_ptr<Dataset>> OpenYcbvDataset(const std::string& root, const std::string& models_dir) {
  try {
    return OpenYcbv(root, models_dir);
  } catch (const std::exception& e) {
    return Internal(root + ": cannot open YCB-Video dataset (" + e.what() + ")");
  }
}

}  // namespace mcpose::io

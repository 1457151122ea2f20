// Datasets: the YCB-Video native layout and the BOP layout behind one interface.
//
// Ids are BOP ids in both layouts: scene_id = video number (data/0049 -> 49), image_id = frame
// number (000001 -> 1), obj_id = YCB-Video cls_index (1-based line of classes.txt). YCB-Video's
// synthetic frames (data_syn/NNNNNN) have scene_id kSyntheticScene; they are not among Frames()
// but load like any other frame (appearance capture reads them).
// Everything comes out in metres, whatever the file stores.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "mcpose/camera.h"
#include "mcpose/image.h"
#include "mcpose/mesh.h"
#include "mcpose/se3.h"
#include "mcpose/status.h"

namespace mcpose {

struct FrameKey {
  int scene_id = 0;
  int image_id = 0;
  auto operator<=>(const FrameKey&) const = default;
};

struct GtInstance {
  int obj_id = 0;
  int gt_index = 0;  // position in meta.mat / scene_gt.json
  SE3 T_cam_obj;     // metres
};

struct Frame {
  FrameKey key;
  Intrinsics K;
  DepthImage depth;  // metres
  std::vector<GtInstance> gt;
  std::string depth_path;  // for error messages
};

enum class DatasetFormat { kYcbv, kBop };

inline constexpr int kSyntheticScene = -1;

class Dataset {
 public:
  virtual ~Dataset() = default;

  // Detects the layout of `root`: YCB-Video if it holds classes.txt and data/, BOP if it holds
  // models/models_info.json and a `split` folder. Errors name the folder and what is missing.
  // `models_dir`, when not empty, replaces root/models as the folder meshes are read from (a
  // folder in the same layout, e.g. one `mcpose capture-appearance` wrote); the objects, their
  // names and the evaluation points stay the dataset's own.
  static StatusOr<std::unique_ptr<Dataset>> Open(const std::string& root, const std::string& split = "test",
                                                 const std::string& models_dir = "");

  virtual DatasetFormat format() const = 0;
  virtual const std::string& root() const = 0;

  // All frames with ground truth, sorted by (scene_id, image_id).
  virtual std::vector<FrameKey> Frames() const = 0;
  // Depth (metres), intrinsics and ground truth of one frame. Validates the depth PNG
  // (16-bit, one channel, size matching the intrinsics) and the intrinsics.
  virtual StatusOr<Frame> LoadFrame(const FrameKey& key) const = 0;
  // The intrinsics (and image size) LoadFrame gives the frame, with the same checks of the
  // camera, read without decoding its depth image (the PNG's header gives the size): what the
  // checks of detections need before a run. This default loads the frame.
  virtual StatusOr<Intrinsics> LoadIntrinsics(const FrameKey& key) const {
    MCPOSE_ASSIGN_OR_RETURN(Frame frame, LoadFrame(key));
    return frame.K;
  }
  // The colour image of a loaded frame as RGBA, alpha 255 everywhere (YCB-Video `-color.png`,
  // whose synthetic frames carry an unrelated alpha channel; BOP `rgb/` PNG or JPEG). Errors
  // name the file: missing, truncated, not 8-bit, or of another size than the frame's depth
  // image.
  virtual StatusOr<ColourImage> LoadColour(const Frame& frame) const = 0;
  // "0049/000001" (YCB-Video; "data_syn/000001" for a synthetic frame) or "000049/000001"
  // (BOP): the name a frame list gives it, and back. ParseFrameName accepts the numbers with
  // or without leading zeros and fails, naming the text, for a frame the dataset does not have.
  virtual std::string FrameName(const FrameKey& key) const = 0;
  virtual StatusOr<FrameKey> ParseFrameName(const std::string& name) const = 0;

  // Visible-part mask of ground-truth instance `gt_index` (label.png == obj_id in YCB-Video,
  // mask_visib/ in BOP). An all-zero mask is valid (object out of view).
  virtual StatusOr<MaskImage> LoadVisibleMask(const FrameKey& key, const GtInstance& gt) const = 0;

  // obj_ids of the models this dataset has, sorted.
  virtual std::vector<int> ObjectIds() const = 0;
  // "003_cracker_box" for YCB-Video; for BOP the YCB-Video name when the ids are YCB-Video's
  // (21 models), else "obj_000003".
  virtual std::string ObjectName(int obj_id) const = 0;
  // The model mesh in metres, validated (Mesh::Validate), with its appearance where the model
  // has one (texture or vertex colours). Unknown obj_id is an error.
  virtual StatusOr<Mesh> LoadMesh(int obj_id) const = 0;
  // Where LoadMesh reads obj_id's model: its folder (YCB-Video: models/<name>/) or file (BOP:
  // models/obj_NNNNNN.ply), under the models folder in use.
  virtual std::string ModelPath(int obj_id) const = 0;
  // The models folder in use (root/models, or the `models_dir` given to Open).
  virtual const std::string& models_dir() const = 0;
  // Points used by ADD / ADD-S, metres: points.xyz (YCB-Video) or the model vertices (BOP).
  virtual StatusOr<std::vector<Eigen::Vector3f>> LoadEvalPoints(int obj_id) const = 0;
};

}  // namespace mcpose

// An in-memory Dataset for the eval unit tests: frames with ground-truth instances, a visible
// mask per instance and evaluation points per object, plus injectable errors.
#pragma once

#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "mcpose/dataset.h"

namespace mcpose::eval_testing {

// A width x height mask with the half-open rectangle [x0, x1) x [y0, y1) set.
inline MaskImage RectMask(int width, int height, int x0, int y0, int x1, int y1) {
  MaskImage m;
  m.width = width;
  m.height = height;
  m.values.assign(static_cast<size_t>(width) * height, 0);
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) m.values[static_cast<size_t>(y) * width + x] = 1;
  }
  return m;
}

class FakeDataset : public Dataset {
 public:
  struct Instance {
    GtInstance gt;
    MaskImage mask;
  };

  FakeDataset(int width, int height) : width_(width), height_(height) {}

  int width() const { return width_; }
  int height() const { return height_; }

  // Adds an instance to a frame (creating the frame); gt_index is its position in the frame.
  void AddInstance(const FrameKey& key, int obj_id, const SE3& T_cam_obj, MaskImage mask) {
    auto& list = frames_[key];
    Instance inst;
    inst.gt.obj_id = obj_id;
    inst.gt.gt_index = static_cast<int>(list.size());
    inst.gt.T_cam_obj = T_cam_obj;
    inst.mask = std::move(mask);
    list.push_back(std::move(inst));
  }
  void SetEvalPoints(int obj_id, std::vector<Eigen::Vector3f> points) {
    points_[obj_id] = std::move(points);
  }

  Status eval_points_error;   // returned by LoadEvalPoints when not ok
  Status visible_mask_error;  // returned by LoadVisibleMask when not ok
  mutable int eval_point_loads = 0;

  DatasetFormat format() const override { return DatasetFormat::kBop; }
  const std::string& root() const override { return root_; }

  std::vector<FrameKey> Frames() const override {
    std::vector<FrameKey> keys;
    for (const auto& [key, instances] : frames_) keys.push_back(key);
    return keys;
  }

  StatusOr<Frame> LoadFrame(const FrameKey& key) const override {
    const auto it = frames_.find(key);
    if (it == frames_.end()) return NotFound("fake: no frame");
    Frame f;
    f.key = key;
    f.K.fx = f.K.fy = 500;
    f.K.cx = width_ / 2.0;
    f.K.cy = height_ / 2.0;
    f.K.width = width_;
    f.K.height = height_;
    f.depth.width = width_;
    f.depth.height = height_;
    f.depth.depth_m.assign(static_cast<size_t>(width_) * height_, 1.0f);
    for (const Instance& inst : it->second) f.gt.push_back(inst.gt);
    return f;
  }

  StatusOr<MaskImage> LoadVisibleMask(const FrameKey& key, const GtInstance& gt) const override {
    if (!visible_mask_error.ok()) return visible_mask_error;
    const auto it = frames_.find(key);
    if (it == frames_.end() || gt.gt_index < 0 ||
        gt.gt_index >= static_cast<int>(it->second.size())) {
      return NotFound("fake: no instance");
    }
    return it->second[static_cast<size_t>(gt.gt_index)].mask;
  }

  // Every class with evaluation points or an instance has a model, except those listed here.
  std::set<int> without_model;

  std::vector<int> ObjectIds() const override {
    std::set<int> ids;
    for (const auto& [id, pts] : points_) ids.insert(id);
    for (const auto& [key, instances] : frames_)
      for (const Instance& inst : instances) ids.insert(inst.gt.obj_id);
    for (int id : without_model) ids.erase(id);
    return {ids.begin(), ids.end()};
  }
  std::string ObjectName(int obj_id) const override { return "fake_" + std::to_string(obj_id); }
  StatusOr<Mesh> LoadMesh(int /*obj_id*/) const override { return NotFound("fake: no meshes"); }
  std::string ModelPath(int obj_id) const override { return "fake/" + std::to_string(obj_id); }
  const std::string& models_dir() const override { return root_; }
  StatusOr<ColourImage> LoadColour(const Frame&) const override { return NotFound("fake: no colour"); }
  std::string FrameName(const FrameKey& key) const override {
    return std::to_string(key.scene_id) + "/" + std::to_string(key.image_id);
  }
  StatusOr<FrameKey> ParseFrameName(const std::string& name) const override {
    return NotFound("fake: no frame " + name);
  }

  StatusOr<std::vector<Eigen::Vector3f>> LoadEvalPoints(int obj_id) const override {
    ++eval_point_loads;
    if (!eval_points_error.ok()) return eval_points_error;
    const auto it = points_.find(obj_id);
    if (it == points_.end()) return NotFound("fake: no points for " + std::to_string(obj_id));
    return it->second;
  }

 private:
  int width_, height_;
  std::string root_ = "fake_root";
  std::map<FrameKey, std::vector<Instance>> frames_;
  std::map<int, std::vector<Eigen::Vector3f>> points_;
};

}  // namespace mcpose::eval_testing

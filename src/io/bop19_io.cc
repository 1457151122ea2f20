// The BOP19 evaluation's inputs: models_info.json (diameters and symmetries) and
// test_targets_bop19.json.

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "mcpose/limits.h"
#include "mcpose/json_util.h"
#include "mcpose/bop19.h"

namespace mcpose {
using nlohmann::json;

StatusOr<std::map<int, ModelInfo>> ReadModelsInfo(const std::string& path) {
  MCPOSE_ASSIGN_OR_RETURN(const json root, io::ReadJsonFile(path));
  if (!root.is_object() || root.empty()) return InvalidArgument(path + ": expected a non-empty object keyed by obj_id");
  std::map<int, ModelInfo> out;
  for (const auto& [key, entry] : root.items()) {
    int obj_id = 0;
    if (!io::IsIdKey(key) || (obj_id = std::stoi(key)) < 1)
      return InvalidArgument(path + ": key '" + key + "' is not a positive obj_id (digits, no leading zero)");
    const std::string where = path + ": obj_id " + key + ": ";
    if (!entry.is_object()) return InvalidArgument(where + "expected an object");
    ModelInfo info;
    double diameter_mm = 0;
    if (!entry.contains("diameter") || !io::JsonToDouble(entry["diameter"], &diameter_mm) || !(diameter_mm > 0) ||
        diameter_mm > 2000 * limits::kMaxCoordinateM)
      return InvalidArgument(where + "'diameter' must be a positive size in mm under " +
                             limits::Num(2000 * limits::kMaxCoordinateM));
    info.diameter_m = diameter_mm / 1000;
    if (entry.contains("symmetries_discrete")) {
      const json& list = entry["symmetries_discrete"];
      if (!list.is_array()) return InvalidArgument(where + "'symmetries_discrete' must be a list");
      for (size_t i = 0; i < list.size(); ++i) {
        double m[16];
        const std::string at = where + "symmetries_discrete[" + std::to_string(i) + "]: ";
        if (!io::JsonToDoubles(list[i], 16, m)) return InvalidArgument(at + "expected 16 finite numbers (a 4x4 matrix)");
        Eigen::Matrix3d R;
        Eigen::Vector3d t;
        for (int r = 0; r < 3; ++r) {
          for (int c = 0; c < 3; ++c) R(r, c) = m[4 * r + c];
          t(r) = m[4 * r + 3] / 1000;
        }
        if (m[12] != 0 || m[13] != 0 || m[14] != 0 || m[15] != 1)
          return InvalidArgument(at + "the last row must be 0 0 0 1");
        if (std::string problem = limits::CheckRotation(R); !problem.empty()) return InvalidArgument(at + problem);
        if (std::string problem = limits::CheckCoordinates(t); !problem.empty()) return InvalidArgument(at + problem);
        info.discrete.emplace_back(R, t);
      }
    }
    if (entry.contains("symmetries_continuous")) {
      const json& list = entry["symmetries_continuous"];
      if (!list.is_array()) return InvalidArgument(where + "'symmetries_continuous' must be a list");
      for (size_t i = 0; i < list.size(); ++i) {
        const std::string at = where + "symmetries_continuous[" + std::to_string(i) + "]: ";
        double axis[3], offset[3];
        if (!list[i].is_object() || !list[i].contains("axis") || !list[i].contains("offset") ||
            !io::JsonToDoubles(list[i]["axis"], 3, axis) || !io::JsonToDoubles(list[i]["offset"], 3, offset))
          return InvalidArgument(at + "expected {\"axis\": [3 numbers], \"offset\": [3 numbers]}");
        ContinuousSymmetry s;
        s.axis = Eigen::Vector3d(axis[0], axis[1], axis[2]);
        s.offset_m = Eigen::Vector3d(offset[0], offset[1], offset[2]) / 1000;
        if (!(s.axis.norm() > 1e-9)) return InvalidArgument(at + "the axis has no length");
        if (std::string problem = limits::CheckCoordinates(s.offset_m); !problem.empty())
          return InvalidArgument(at + problem);
        s.axis.normalize();
        info.continuous.push_back(s);
      }
    }
    out.emplace(obj_id, std::move(info));
  }
  return out;
}

StatusOr<std::vector<Bop19Target>> ReadBop19Targets(const std::string& path) {
  MCPOSE_ASSIGN_OR_RETURN(const json root, io::ReadJsonFile(path));
  if (!root.is_array()) return InvalidArgument(path + ": expected a list of targets");
  std::vector<Bop19Target> out;
  for (size_t i = 0; i < root.size(); ++i) {
    const json& t = root[i];
    Bop19Target target;
    const std::string at = path + ": target " + std::to_string(i) + ": ";
    if (!t.is_object()) return InvalidArgument(at + "expected an object");
    for (const char* key : {"scene_id", "im_id", "obj_id", "inst_count"})
      if (!t.contains(key)) return InvalidArgument(at + "missing '" + key + "'");
    if (!io::JsonToInt(t["scene_id"], &target.key.scene_id) || !io::JsonToInt(t["im_id"], &target.key.image_id) ||
        !io::JsonToInt(t["obj_id"], &target.obj_id) || !io::JsonToInt(t["inst_count"], &target.inst_count) ||
        target.key.scene_id < 0 || target.key.image_id < 0 || target.obj_id < 1 || target.inst_count < 1)
      return InvalidArgument(at + "scene_id and im_id must be whole numbers >= 0, obj_id and inst_count >= 1");
    out.push_back(target);
  }
  return out;
}

}  // namespace mcpose

#include "report/estimate_detail.h"

#include "io/json_util.h"

namespace mcpose::report {
namespace {

// The problem with one entry of objects[], or empty.
std::string ParseObject(const nlohmann::json& o, ObjectDetail* d) {
  if (!o.is_object()) return "is not an object";
  const auto int_field = [&](const char* name, int* out) {
    return o.contains(name) && io::JsonToInt(o[name], out);
  };
  if (!int_field("scene_id", &d->key.scene_id)) return "scene_id is missing or not an integer";
  if (!int_field("im_id", &d->key.image_id)) return "im_id is missing or not an integer";
  if (!int_field("obj_id", &d->obj_id)) return "obj_id is missing or not an integer";
  if (o.contains("boxes") && !io::JsonToInt(o["boxes"], &d->boxes)) return "boxes is not an integer";
  double R[9], t_mm[3];
  if (!o.contains("R") || !io::JsonToDoubles(o["R"], 9, R)) return "R must be 9 finite numbers";
  if (!o.contains("t_mm") || !io::JsonToDoubles(o["t_mm"], 3, t_mm)) return "t_mm must be 3 finite numbers";
  for (int i = 0; i < 9; ++i) d->T_cam_obj.R(i / 3, i % 3) = R[i];
  for (int i = 0; i < 3; ++i) d->T_cam_obj.t(i) = t_mm[i] / 1000.0;

  if (!o.contains("chosen_box") || !o["chosen_box"].is_object()) return "chosen_box is missing";
  const nlohmann::json& box = o["chosen_box"];
  double bbox[4];
  if (!box.contains("bbox") || !io::JsonToDoubles(box["bbox"], 4, bbox)) return "chosen_box.bbox must be 4 finite numbers";
  if (!box.contains("score") || !io::JsonToDouble(box["score"], &d->chosen_box.score))
    return "chosen_box.score is missing or not a number";
  d->chosen_box.scene_id = d->key.scene_id, d->chosen_box.image_id = d->key.image_id;
  d->chosen_box.obj_id = d->obj_id;
  d->chosen_box.x = bbox[0], d->chosen_box.y = bbox[1], d->chosen_box.w = bbox[2], d->chosen_box.h = bbox[3];

  if (!o.contains("per_iteration") || !o["per_iteration"].is_array()) return "per_iteration is missing or not a list";
  for (size_t i = 0; i < o["per_iteration"].size(); ++i) {
    const nlohmann::json& it = o["per_iteration"][i];
    IterationWeights w;
    if (!it.is_object() || !it.contains("mean_weight") || !io::JsonToDouble(it["mean_weight"], &w.mean_weight) ||
        !it.contains("best_weight") || !io::JsonToDouble(it["best_weight"], &w.best_weight))
      return "per_iteration[" + std::to_string(i) + "] needs numbers mean_weight and best_weight";
    d->per_iteration.push_back(w);
  }
  // Optional numbers.
  const auto number = [&](const nlohmann::json& j, const char* name, double* out) {
    if (j.is_object() && j.contains(name)) io::JsonToDouble(j[name], out);
  };
  number(o, "best_weight", &d->best_weight);
  number(o, "final_mean_weight", &d->final_mean_weight);
  number(o, "time_s", &d->time_s);
  if (o.contains("twins") && o["twins"].is_object()) {
    const nlohmann::json& t = o["twins"];
    if (t.contains("ran") && t["ran"].is_boolean()) d->twins_ran = t["ran"].get<bool>();
    if (t.contains("candidates")) io::JsonToInt(t["candidates"], &d->twin_candidates);
  }
  if (o.contains("refine") && o["refine"].is_object()) {
    const nlohmann::json& r = o["refine"];
    if (r.contains("accepted") && r["accepted"].is_boolean()) d->refine_accepted = r["accepted"].get<bool>();
    double before = NAN, after = NAN;
    number(r, "rms_before_m", &before);
    number(r, "rms_after_m", &after);
    d->refine_rms_before_mm = 1000 * before, d->refine_rms_after_mm = 1000 * after;
  }
  return {};
}

}  // namespace

StatusOr<EstimateDetail> ReadEstimateDetail(const std::string& path) {
  MCPOSE_ASSIGN_OR_RETURN(nlohmann::json doc, io::ReadJsonFile(path));
  if (!doc.is_object() || !doc.contains("objects") || !doc["objects"].is_array())
    return InvalidArgument(path + ": expected an object with a list 'objects' (the file `mcpose estimate --out-json` writes)");
  EstimateDetail detail;
  if (doc.contains("options") && doc["options"].is_object() && doc["options"].contains("tau"))
    io::JsonToDouble(doc["options"]["tau"], &detail.tau);
  const nlohmann::json& objects = doc["objects"];
  for (size_t i = 0; i < objects.size(); ++i) {
    ObjectDetail d;
    const std::string problem = ParseObject(objects[i], &d);
    if (!problem.empty()) return InvalidArgument(path + ": objects[" + std::to_string(i) + "]: " + problem);
    detail.objects.push_back(std::move(d));
  }
  return detail;
}

}  // namespace mcpose::report

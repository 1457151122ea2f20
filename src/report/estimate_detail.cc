#include "mcpose/estimate_detail.h"

#include "mcpose/json_util.h"
#include "mcpose/options_json.h"
#include "mcpose/simd.h"

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

namespace {

nlohmann::json ObjectJson(const ObjectRecord& r) {
  const ObjectEstimate& e = r.estimate;
  nlohmann::json R = nlohmann::json::array(), t = nlohmann::json::array();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R.push_back(e.T_cam_obj.R(i, j));
  for (int i = 0; i < 3; ++i) t.push_back(e.T_cam_obj.t(i) * 1000.0);
  nlohmann::json per_iteration = nlohmann::json::array();
  for (const IterationSummary& it : e.iterations)
    per_iteration.push_back({{"mean_weight", it.mean_weight},
                             {"best_weight", it.best_weight},
                             {"score_ms", it.score_ms},
                             {"iteration_ms", it.iteration_ms}});
  return {
      {"scene_id", r.key.scene_id},
      {"im_id", r.key.image_id},
      {"obj_id", r.obj_id},
      {"instance", r.instance},
      {"name", r.name},
      {"boxes", r.num_boxes},
      {"chosen_box", {{"bbox", {r.chosen_box.x, r.chosen_box.y, r.chosen_box.w, r.chosen_box.h}},
                      {"score", r.chosen_box.score},
                      {"index", e.best_box}}},
      {"iterations", e.iterations.size()},
      {"best_weight", e.best_weight},
      {"final_mean_weight", e.final_mean_weight()},
      {"per_iteration", per_iteration},
      {"R", R},
      {"t_mm", t},
      {"time_s", r.time_s},
      {"box_triangles", e.box_triangles},
      {"depth_pixels_read", e.depth_pixels_read},
      {"colour", e.colour},
      {"twins", {{"ran", e.twins.ran}, {"candidates", e.twins.candidates}, {"winner", e.twins.winner},
                 {"winner_weight", e.twins.winner_weight}, {"margin", e.twins.margin},
                 {"refine_iterations", e.twins.refine_iterations}, {"ms", e.twins.ms}}},
      {"refine", {{"ran", e.refine.ran}, {"accepted", e.refine.accepted}, {"iterations", e.refine.iterations},
                  {"pairs", e.refine.pairs}, {"rms_before_m", e.refine.rms_before_m},
                  {"rms_after_m", e.refine.rms_after_m}, {"weight_before", e.refine.weight_before},
                  {"weight_after", e.refine.weight_after}, {"ms", e.refine.ms}}},
      {"counters", io::CountersToJson(e.Totals())},
  };
}

nlohmann::json PoseJson(const SE3& T, nlohmann::json* t_mm) {
  nlohmann::json R = nlohmann::json::array();
  *t_mm = nlohmann::json::array();
  for (int i = 0; i < 9; ++i) R.push_back(T.R(i / 3, i % 3));
  for (int i = 0; i < 3; ++i) t_mm->push_back(1000 * T.t(i));
  return R;
}

}  // namespace

nlohmann::json EstimateDetailJson(const RunReport& report, const EstimatorOptions& options, const std::string& dataset,
                                  const std::string& models, const std::string& detections) {
  nlohmann::json objects = nlohmann::json::array();
  for (const ObjectRecord& r : report.objects) objects.push_back(ObjectJson(r));
  nlohmann::json o = io::OptionsToJson(options);
  o["engine"]["simd_target"] = render::DispatchedSimdTarget(options.engine.simd_target);  // the name, not "best"
  return {{"dataset", dataset}, {"models", models}, {"detections", detections}, {"options", o}, {"objects", objects}};
}

nlohmann::json TrackDetailJson(const TrackReport& report, const TrackerOptions& options, const std::string& dataset,
                               int video) {
  nlohmann::json steps = nlohmann::json::array();
  for (const TrackRecord& r : report.steps) {
    const TrackStep& step = r.step;
    nlohmann::json t;
    const nlohmann::json R = PoseJson(step.T_cam_obj, &t);
    steps.push_back({{"scene_id", r.key.scene_id}, {"im_id", r.key.image_id}, {"obj_id", step.obj_id},
                     {"name", r.name}, {"initialised", step.initialised}, {"lost", step.lost},
                     {"weight", step.weight}, {"fit", step.fit}, {"visible", step.visible},
                     {"iterations", step.iterations}, {"box", {step.box.x, step.box.y, step.box.w, step.box.h}},
                     {"ms", step.ms}, {"R", R}, {"t_mm", t}});
  }
  return {{"dataset", dataset}, {"video", video}, {"options", io::TrackerOptionsToJson(options)}, {"steps", steps}};
}

}  // namespace mcpose::report

// The report folder: sections per image built from the evaluation, drawn with the overlay
// functions, written as one HTML page with inline SVG and PNG images beside it.
#include "mcpose/report.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <tuple>

#include "engine/box_scorer.h"
#include "mcpose/run.h"
#include "mcpose/io_util.h"
#include "mcpose/png_io.h"
#include "report/overlay.h"
#include "report/svg.h"

namespace mcpose::report {
namespace {

namespace fs = std::filesystem;
using ResultKey = std::tuple<int, int, int>;  // (scene_id, im_id, obj_id)

// Kelly's colours of maximum contrast, without white, black and grey: distinct on a photo.
constexpr std::array<Rgba8, 19> kPalette = {{
    {243, 195, 0, 255},   {135, 86, 146, 255}, {243, 132, 0, 255},  {161, 202, 241, 255}, {190, 0, 50, 255},
    {194, 178, 128, 255}, {0, 136, 86, 255},   {230, 143, 172, 255}, {0, 103, 165, 255},  {249, 147, 121, 255},
    {96, 78, 151, 255},   {246, 166, 0, 255},  {179, 68, 108, 255}, {220, 211, 0, 255},   {136, 45, 23, 255},
    {141, 182, 0, 255},   {101, 69, 34, 255},  {226, 88, 34, 255},  {43, 61, 38, 255}}};

// Pixels of the residual figure's longer side in the page (the PNG keeps the box's own size).
constexpr int kResidualDisplayPx = 200;
// Margin around an estimate's silhouette when there is no chosen box to show the residual in.
constexpr int kSilhouetteMarginPx = 8;
// Rows of the worst-first table shown before the rest folds away.
constexpr size_t kWorstShown = 10;

std::string Printf(const char* format, ...) __attribute__((format(printf, 1, 2)));
std::string Printf(const char* format, ...) {
  char buffer[512];
  va_list args;
  va_start(args, format);
  std::vsnprintf(buffer, sizeof buffer, format, args);
  va_end(args);
  return buffer;
}

// A distance in metres as millimetres, "missed" for no result.
std::string Millimetres(double m) { return std::isfinite(m) ? Printf("%.1f", 1000 * m) : "missed"; }
std::string Percent(double share) { return Printf("%.1f", 100 * share); }
std::string Or(bool have, const std::string& text) { return have ? text : "&ndash;"; }

// One object in one image: a ground-truth target, a result, or both.
struct Entry {
  int obj_id = 0;
  std::string name;
  const InstanceEval* eval = nullptr;  // null: a result with no visible instance to score against
  const PoseResult* result = nullptr;  // null: the target was missed
  const ObjectDetail* detail = nullptr;
  std::string anchor;
  // Filled when the image is drawn.
  std::string residual_file;
  render::PixelRect residual_rect;
  ResidualStats residual;
  bool chosen_is_distractor = false;
};

// Larger is worse: missed targets (infinite error) first, results without a target last.
double SortError(const Entry& e) { return e.eval ? e.eval->add_or_adds_m : -1; }

struct Box {
  Detection d;
  bool distractor = false;
  bool chosen = false;
};

struct Section {
  FrameKey key;
  std::string name;       // the dataset's frame name, "0049/000001"
  std::string stem;       // the same for file names, "0049_000001"
  std::string image_file;  // relative to the report folder
  bool depth_only = false;  // no colour frame: the depth is shown
  int width = 0, height = 0;
  std::vector<Entry> entries;
  std::vector<Box> boxes;
  double worst = -1;
};

// The verdict of an entry as a CSS class and a word.
std::pair<const char*, const char*> Verdict(const Entry& e) {
  if (!e.eval) return {"warn", "no target"};
  if (!e.eval->has_result) return {"fail", "missed"};
  if (e.eval->add_or_adds_m < 0.02) return {"ok", "&lt; 2 cm"};
  if (e.eval->add_or_adds_m < 0.04) return {"warn", "&lt; 4 cm"};
  return {"fail", "&ge; 4 cm"};
}

bool SameBox(const Detection& a, const Detection& b) {
  return a.obj_id == b.obj_id && std::fabs(a.x - b.x) < 1e-6 && std::fabs(a.y - b.y) < 1e-6 &&
         std::fabs(a.w - b.w) < 1e-6 && std::fabs(a.h - b.h) < 1e-6 && std::fabs(a.score - b.score) < 1e-9;
}

render::PixelRect GrowClip(const render::PixelRect& r, int margin, int width, int height) {
  return {std::max(0, r.x0 - margin), std::max(0, r.y0 - margin), std::min(width, r.x1 + margin),
          std::min(height, r.y1 + margin)};
}

// The tight pixel rect of a mask's nonzero pixels; empty for an empty mask.
render::PixelRect MaskRect(const MaskImage& mask) {
  Detection box;
  if (MaskBox(mask, &box) == 0) return {};
  return {static_cast<int>(box.x), static_cast<int>(box.y), static_cast<int>(box.x + box.w),
          static_cast<int>(box.y + box.h)};
}

// ---- Building the sections ----------------------------------------------------------------

struct Model {
  const Dataset* dataset;
  const ReportInput* input;
  EvalReport eval;
  std::map<ResultKey, const PoseResult*> best;  // the row Evaluate scores, per key
  std::map<ResultKey, const ObjectDetail*> detail;
  std::vector<Section> sections;
};

// Every results row names an image and a class of the dataset, every box passes
// CheckDetectionsAgainstDataset; the error names the file.
Status CheckAgainstDataset(const Dataset& dataset, const ReportInput& in) {
  std::set<FrameKey> frames;
  for (const FrameKey& k : dataset.Frames()) frames.insert(k);
  const std::vector<int> ids = dataset.ObjectIds();
  const std::set<int> classes(ids.begin(), ids.end());
  const auto check = [&](const std::string& where, int scene_id, int image_id, int obj_id) {
    if (!frames.contains(FrameKey{scene_id, image_id}))
      return InvalidArgument(where + ": the dataset " + dataset.root() + " has no such image");
    if (!classes.contains(obj_id))
      return InvalidArgument(where + ": obj_id " + std::to_string(obj_id) + " is not a class of the dataset " +
                             dataset.root());
    return Status::Ok();
  };
  for (const PoseResult& r : in.results)
    MCPOSE_RETURN_IF_ERROR(check(in.results_path + ": a row of scene_id " + std::to_string(r.scene_id) + ", im_id " +
                                     std::to_string(r.im_id),
                                 r.scene_id, r.im_id, r.obj_id));
  if (in.detections) MCPOSE_RETURN_IF_ERROR(CheckDetectionsAgainstDataset(dataset, *in.detections, in.detections_path));
  return Status::Ok();
}

Status CollectSections(Model* m) {
  const ReportInput& in = *m->input;
  for (const PoseResult& r : in.results) {
    auto [it, inserted] = m->best.try_emplace(ResultKey{r.scene_id, r.im_id, r.obj_id}, &r);
    if (!inserted && r.score > it->second->score) it->second = &r;
  }
  if (in.detail) {
    // The report shows each (image, class)'s best row; its detail is the object with its pose
    // (a class with several instances has one detail object each).
    std::map<ResultKey, size_t> other_pose;  // a key's first detail object whose pose is not its row's
    for (size_t i = 0; i < in.detail->objects.size(); ++i) {
      const ObjectDetail& d = in.detail->objects[i];
      const ResultKey key{d.key.scene_id, d.key.image_id, d.obj_id};
      const auto row = m->best.find(key);
      if (row == m->best.end()) continue;  // an object the results leave out
      const SE3& T = row->second->T_cam_obj;
      // The CSV carries 9 significant digits of R and micrometres of t.
      if ((T.R - d.T_cam_obj.R).cwiseAbs().maxCoeff() > 1e-6 || (T.t - d.T_cam_obj.t).norm() > 1e-5)
        other_pose.try_emplace(key, i);
      else
        m->detail[key] = &d;
    }
    for (const auto& [key, i] : other_pose) {
      if (m->detail.count(key)) continue;
      const ObjectDetail& d = in.detail->objects[i];
      return InvalidArgument(in.detail_path + ": objects[" + std::to_string(i) + "] (scene_id " +
                             std::to_string(d.key.scene_id) + ", im_id " + std::to_string(d.key.image_id) +
                             ", obj_id " + std::to_string(d.obj_id) + ") has another pose than " +
                             in.results_path + ": not the run that wrote the results");
    }
  }

  std::map<FrameKey, Section> by_frame;
  const auto section = [&](const FrameKey& key) -> Section& {
    Section& s = by_frame[key];
    if (s.name.empty()) {
      s.key = key;
      s.name = m->dataset->FrameName(key);
      s.stem = s.name;
      std::replace(s.stem.begin(), s.stem.end(), '/', '_');
    }
    return s;
  };
  const auto make_entry = [&](const FrameKey& key, int obj_id) {
    Entry e;
    e.obj_id = obj_id;
    e.name = m->dataset->ObjectName(obj_id);
    const ResultKey rk{key.scene_id, key.image_id, obj_id};
    if (const auto it = m->best.find(rk); it != m->best.end()) e.result = it->second;
    if (const auto it = m->detail.find(rk); it != m->detail.end()) e.detail = it->second;
    return e;
  };
  std::set<ResultKey> with_target;
  for (const InstanceEval& inst : m->eval.instances) {
    Entry e = make_entry(inst.key, inst.obj_id);
    e.eval = &inst;
    if (!inst.has_result) e.result = nullptr, e.detail = nullptr;
    e.anchor = Printf("s%d-i%d-o%d-g%d", inst.key.scene_id, inst.key.image_id, inst.obj_id, inst.gt_index);
    section(inst.key).entries.push_back(std::move(e));
    with_target.insert(ResultKey{inst.key.scene_id, inst.key.image_id, inst.obj_id});
  }
  for (const auto& [rk, row] : m->best) {
    if (with_target.contains(rk)) continue;
    const FrameKey key{row->scene_id, row->im_id};
    Entry e = make_entry(key, row->obj_id);
    e.anchor = Printf("s%d-i%d-o%d-r", key.scene_id, key.image_id, row->obj_id);
    section(key).entries.push_back(std::move(e));
  }
  if (in.detections) {
    for (const Detection& d : *in.detections)
      if (by_frame.contains(FrameKey{d.scene_id, d.image_id})) section(FrameKey{d.scene_id, d.image_id}).boxes.push_back({d});
  }

  for (auto& [key, s] : by_frame) {
    std::stable_sort(s.entries.begin(), s.entries.end(),
                     [](const Entry& a, const Entry& b) { return SortError(a) > SortError(b); });
    for (const Entry& e : s.entries) s.worst = std::max(s.worst, SortError(e));
    m->sections.push_back(std::move(s));
  }
  std::stable_sort(m->sections.begin(), m->sections.end(),
                   [](const Section& a, const Section& b) { return a.worst > b.worst; });
  return Status::Ok();
}

// ---- Drawing one image --------------------------------------------------------------------

class MeshCache {
 public:
  explicit MeshCache(const Dataset& dataset) : dataset_(&dataset) {}
  StatusOr<const Mesh*> Get(int obj_id) {
    auto it = meshes_.find(obj_id);
    if (it == meshes_.end()) {
      MCPOSE_ASSIGN_OR_RETURN(Mesh mesh, dataset_->LoadMesh(obj_id));
      it = meshes_.emplace(obj_id, std::move(mesh)).first;
    }
    return &it->second;
  }

 private:
  const Dataset* dataset_;
  std::map<int, Mesh> meshes_;
};

Status DrawSection(const Dataset& dataset, const ReportInput& in, MeshCache* meshes, const fs::path& dir,
                   Section* s) {
  MCPOSE_ASSIGN_OR_RETURN(const Frame frame, dataset.LoadFrame(s->key));
  s->width = frame.K.width, s->height = frame.K.height;
  StatusOr<ColourImage> loaded = dataset.LoadColour(frame);
  if (!loaded.ok() && loaded.status().code() != StatusCode::kNotFound) return loaded.status();
  s->depth_only = !loaded.ok();
  const ColourImage base = loaded.ok() ? std::move(loaded).value() : DepthAsColour(frame.depth);
  ColourImage drawn = base;

  // Distractors: boxes over no visible pixel of their class.
  if (!s->boxes.empty()) {
    std::map<int, std::vector<MaskImage>> visible;
    for (const GtInstance& gt : frame.gt) {
      MCPOSE_ASSIGN_OR_RETURN(MaskImage mask, dataset.LoadVisibleMask(s->key, gt));
      visible[gt.obj_id].push_back(std::move(mask));
    }
    for (Box& b : s->boxes) b.distractor = IsDistractor(b.d, visible[b.d.obj_id]);
  }
  for (Entry& e : s->entries) {
    if (!e.detail) continue;
    for (Box& b : s->boxes)
      if (SameBox(b.d, e.detail->chosen_box)) b.chosen = true, e.chosen_is_distractor = b.distractor;
  }

  // The ground truth underneath, wider and dashed: where an estimate coincides, both show.
  if (in.draw_ground_truth) {
    OutlineStyle gt_style;
    gt_style.dashed = true;
    gt_style.radius_px = 2;
    for (const GtInstance& gt : frame.gt) {
      MCPOSE_ASSIGN_OR_RETURN(const Mesh* mesh, meshes->Get(gt.obj_id));
      DrawOutline(Outline(Silhouette(RenderDepth(*mesh, gt.T_cam_obj, frame.K))), gt_style, &drawn);
    }
  }
  // The estimates, once per result (two instances of a class share one), with their residual.
  std::map<int, const Entry*> drawn_results;
  for (Entry& e : s->entries) {
    if (!e.result) continue;
    if (const auto it = drawn_results.find(e.obj_id); it != drawn_results.end()) {
      e.residual_file = it->second->residual_file, e.residual_rect = it->second->residual_rect;
      e.residual = it->second->residual;
      continue;
    }
    MCPOSE_ASSIGN_OR_RETURN(const Mesh* mesh, meshes->Get(e.obj_id));
    const DepthImage rendered = RenderDepth(*mesh, e.result->T_cam_obj, frame.K);
    const MaskImage silhouette = Silhouette(rendered);
    OutlineStyle style;
    style.colour = ObjectColour(e.obj_id);
    DrawOutline(Outline(silhouette), style, &drawn);
    e.residual_rect = e.detail ? engine::ClipBox(e.detail->chosen_box.x, e.detail->chosen_box.y,
                                                 e.detail->chosen_box.w, e.detail->chosen_box.h, s->width, s->height)
                               : GrowClip(MaskRect(silhouette), kSilhouetteMarginPx, s->width, s->height);
    if (!e.residual_rect.empty()) {
      const ColourImage residual = DepthResidualImage(frame.depth, rendered, base, e.residual_rect,
                                                      in.residual_limit_m, in.inlier_m, &e.residual);
      e.residual_file = "images/" + s->stem + Printf("_obj%02d_residual.png", e.obj_id);
      MCPOSE_RETURN_IF_ERROR(io::WriteColourPng((dir / e.residual_file).string(), residual));
    }
    drawn_results[e.obj_id] = &e;
  }
  s->image_file = "images/" + s->stem + ".png";
  return io::WriteColourPng((dir / s->image_file).string(), drawn);
}

// ---- The page -----------------------------------------------------------------------------

constexpr const char* kStyle = R"(
body{font-family:sans-serif;margin:16px;color:#222;max-width:1260px}
h1{font-size:21px;margin:0 0 6px} h2{font-size:17px;margin:26px 0 8px;padding-top:10px;border-top:2px solid #bbb}
h3{font-size:14px;margin:0 0 6px}
p,li{font-size:13px} a{color:#0b5cad}
table{border-collapse:collapse;font-size:12px;margin:6px 0}
td,th{padding:2px 6px;border-bottom:1px solid #e6e6e6;text-align:right;white-space:nowrap}
td:first-child,th:first-child,td.l,th.l{text-align:left}
th{background:#f3f3f3}
.sw{display:inline-block;width:11px;height:11px;margin-right:5px;vertical-align:-1px;border:1px solid #0004}
.ok{color:#1a7f37}.warn{color:#a35200}.fail{color:#c62828;font-weight:bold}
.plots{display:flex;gap:16px;flex-wrap:wrap}
.sec{display:flex;flex-wrap:wrap;gap:12px;align-items:flex-start}
.frame{position:relative;line-height:0}
.frame svg{position:absolute;left:0;top:0}
.obj{border:1px solid #ccc;border-radius:4px;padding:8px;width:576px;box-sizing:border-box}
.obj .row{display:flex;gap:10px;align-items:flex-start}
.obj table{width:342px;table-layout:fixed;margin:0}
.obj td{font-size:11.5px;white-space:normal;text-align:left}
.obj td:first-child{width:118px}
.resid{image-rendering:pixelated;border:1px solid #999;display:block}
.note{color:#666;font-size:12px}
)";

std::string Swatch(int obj_id) {
  return "<span class=\"sw\" style=\"background:" + CssColour(ObjectColour(obj_id)) + "\"></span>";
}

std::string AccuracyTable(const EvalReport& eval) {
  std::string s =
      "<table><tr><th rowspan=2>object</th><th rowspan=2>instances</th><th rowspan=2>results</th>"
      "<th colspan=3>ADD, %</th><th colspan=3>ADD-S, %</th><th colspan=3>ADD(-S), %</th></tr><tr>";
  for (int k = 0; k < 3; ++k) s += "<th>&lt;2 cm</th><th>&lt;4 cm</th><th>AUC</th>";
  s += "</tr>";
  const auto row = [&](const AccuracySummary& a, bool all) {
    s += "<tr>" + std::string(all ? "<td><b>ALL</b>" : "<td>" + Swatch(a.obj_id) + EscapeXml(a.name)) + "</td>";
    s += "<td>" + std::to_string(a.instances) + "</td><td>" + std::to_string(a.with_result) + "</td>";
    for (double v : {a.add_lt_2cm, a.add_lt_4cm, a.add_auc, a.adds_lt_2cm, a.adds_lt_4cm, a.adds_auc, a.add_s_lt_2cm,
                     a.add_s_lt_4cm, a.add_s_auc})
      s += "<td>" + Percent(v) + "</td>";
    s += "</tr>";
  };
  for (const AccuracySummary& a : eval.per_object) row(a, false);
  row(eval.overall, true);
  return s + "</table>";
}

// Accuracy against threshold: every object thin in its colour, all instances thick in black.
std::string CurvePlot(const EvalReport& eval, const std::string& id, const std::string& title, double max_m,
                      double InstanceEval::*error) {
  LinePlot plot;
  plot.id = id;
  plot.width_px = 420, plot.height_px = 260;
  plot.title = title;
  plot.x_label = "threshold, cm";
  plot.y_label = "share of instances below, %";
  plot.x_max = 100 * max_m, plot.y_max = 100;
  plot.legend_bottom_right = true;
  const auto series = [&](std::vector<double> errors) {
    std::vector<std::array<double, 2>> points = AccuracyCurve(std::move(errors), max_m);
    for (auto& p : points) p[0] *= 100, p[1] *= 100;
    return points;
  };
  std::map<int, std::vector<double>> by_object;
  std::vector<double> all;
  for (const InstanceEval& e : eval.instances) by_object[e.obj_id].push_back(e.*error), all.push_back(e.*error);
  for (const AccuracySummary& a : eval.per_object)
    plot.series.push_back({a.name, CssColour(ObjectColour(a.obj_id)), series(by_object[a.obj_id]), 1.2, false, false});
  plot.series.push_back({"all instances", "#000", series(all), 2.5, false, true});
  plot.series.push_back({"one object each (hover for its name)", "#999", {}, 1.2, false, true});
  return LinePlotSvg(plot);
}

std::string ConvergencePlot(const Entry& e, double tau, const std::string& id) {
  LinePlot plot;
  plot.id = id;
  plot.width_px = 558, plot.height_px = 150;
  plot.x_integer = true;
  plot.title = "convergence";
  plot.x_label = "iteration";
  plot.y_label = "weight";
  const auto& its = e.detail->per_iteration;
  plot.x_min = 1, plot.x_max = std::max<double>(2, static_cast<double>(its.size()));
  PlotSeries best{"best weight", "#c62828", {}, 1.8, false, true};
  PlotSeries mean{"mean weight", "#1565c0", {}, 1.8, false, true};
  for (size_t i = 0; i < its.size(); ++i) {
    best.points.push_back({static_cast<double>(i + 1), its[i].best_weight});
    mean.points.push_back({static_cast<double>(i + 1), its[i].mean_weight});
  }
  plot.series = {best, mean};
  plot.legend_bottom_right = true;
  if (std::isfinite(tau)) plot.y_rules.push_back({tau, Printf("tau %.2f", tau)});
  return LinePlotSvg(plot);
}

// "[x, y, w, h], score s" to a tenth of a pixel.
std::string BoxWithScore(const Detection& d) {
  return Printf("[%.1f, %.1f, %.1f, %.1f], score %.2f", d.x, d.y, d.w, d.h, d.score);
}

std::string ObjectCard(const Entry& e, const ReportInput& in) {
  const auto [css, word] = Verdict(e);
  std::string s = "<div class=\"obj\" id=\"" + e.anchor + "\"><h3>" + Swatch(e.obj_id) + EscapeXml(e.name) +
                  " &mdash; <span class=\"" + css + "\">ADD(-S) " +
                  (e.eval ? Millimetres(e.eval->add_or_adds_m) + (e.eval->has_result ? " mm" : "") : "&ndash;") +
                  " (" + word + ")</span></h3><div class=\"row\"><table>";
  const auto kv = [&](const std::string& k, const std::string& v) {
    s += "<tr><td class=\"l\">" + k + "</td><td>" + v + "</td></tr>";
  };
  const bool scored = e.eval && e.eval->has_result;
  if (e.eval) {
    kv("ADD / ADD-S", scored ? Millimetres(e.eval->add_m) + " / " + Millimetres(e.eval->adds_m) + " mm" : "missed");
    kv("rotation error", Or(scored, Printf("%.1f&deg;", e.eval->rotation_error_deg)));
    kv("translation error", Or(scored, Printf("%.1f mm", e.eval->translation_error_mm)));
    kv("visible pixels", std::to_string(e.eval->visible_pixels));
  } else {
    kv("ground truth", "no visible instance of this object in the image");
  }
  if (e.result) kv("score (best weight)", Printf("%.3f", e.result->score));
  if (e.detail) {
    const ObjectDetail& d = *e.detail;
    kv("iterations", Printf("%zu, final mean weight %.3f", d.per_iteration.size(), d.final_mean_weight));
    kv("chosen box", BoxWithScore(d.chosen_box) +
                         (in.detections ? (e.chosen_is_distractor ? " <span class=\"fail\">distractor</span>" : "")
                                        : ""));
    kv("boxes of the class", std::to_string(d.boxes));
    if (d.twins_ran) kv("depth twins", Printf("%d candidates compared", d.twin_candidates));
    if (std::isfinite(d.refine_rms_before_mm))
      kv("alignment", Printf("rms %.1f &rarr; %.1f mm, %s", d.refine_rms_before_mm, d.refine_rms_after_mm,
                             d.refine_accepted ? "kept" : "not kept"));
    if (std::isfinite(d.time_s)) kv("time", Printf("%.0f ms", 1000 * d.time_s));
  }
  if (e.result && e.residual.compared_pixels > 0)
    kv("depth agreement", Printf("median |dz| %.1f mm, %s %% within %.0f mm", e.residual.median_abs_mm,
                                 Percent(e.residual.inlier_share).c_str(), 1000 * in.inlier_m));
  s += "</table>";
  if (!e.result) {
    s += "<p class=\"note\">No result row for this object in this image.</p></div></div>";
    return s;
  }
  s += "<div>";
  if (!e.residual_file.empty()) {
    const int w = e.residual_rect.width(), h = e.residual_rect.height();
    const double scale = static_cast<double>(kResidualDisplayPx) / std::max(w, h);
    s += Printf("<img class=\"resid\" src=\"%s\" width=\"%d\" height=\"%d\" alt=\"depth residual\">",
                e.residual_file.c_str(), static_cast<int>(std::lround(w * scale)),
                static_cast<int>(std::lround(h * scale)));
    s += ColourBarSvg("bar-" + e.anchor, DivergingColourStops(), 1000 * in.residual_limit_m, "mm", kResidualDisplayPx + 10);
    s += std::string("<div class=\"note\">observed &minus; rendered depth in the ") +
         (e.detail ? "chosen box" : "estimate's silhouette box") + "; black: no observed depth</div>";
  } else {
    s += "<p class=\"note\">The estimate projects outside the image.</p>";
  }
  s += "</div></div>";
  if (e.detail) s += ConvergencePlot(e, in.detail->tau, "conv-" + e.anchor);
  return s + "</div>";
}

// The boxes of a section as SVG over the frame image: the chosen ones thick, the others thin,
// distractors dashed red with a label.
std::string BoxOverlay(const Section& s, const Dataset& dataset) {
  std::string svg = Printf(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\" "
      "font-family=\"sans-serif\" font-size=\"11\">",
      s.width, s.height, s.width, s.height);
  for (const Box& b : s.boxes) {
    const std::string colour = b.distractor ? "#ff1744" : CssColour(ObjectColour(b.d.obj_id));
    svg += Printf("<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"none\" stroke=\"%s\" "
                  "stroke-width=\"%s\"%s><title>",
                  b.d.x, b.d.y, b.d.w, b.d.h, colour.c_str(), b.chosen ? "2.5" : "1.2",
                  b.distractor ? " stroke-dasharray=\"6 4\"" : "");
    svg += EscapeXml(dataset.ObjectName(b.d.obj_id)) + " " + BoxWithScore(b.d) + (b.chosen ? ", chosen" : "") +
           (b.distractor ? ", distractor" : "") + "</title></rect>";
    const std::string label = EscapeXml(dataset.ObjectName(b.d.obj_id)) + Printf(" %.2f", b.d.score) +
                              (b.distractor ? " distractor" : "") + (b.chosen ? " (chosen)" : "");
    svg += Printf("<text x=\"%.1f\" y=\"%.1f\" fill=\"%s\" stroke=\"#000\" stroke-width=\"3\" "
                  "paint-order=\"stroke\">",
                  std::max(0.0, b.d.x) + 2, std::max(0.0, b.d.y) + 12, colour.c_str()) +
           label + "</text>";
  }
  return svg + "</svg>";
}

std::string SectionHtml(const Section& s, const Dataset& dataset, const ReportInput& in) {
  std::string h = "<h2 id=\"img-" + s.stem + "\">" + EscapeXml(s.name) + " &mdash; worst ADD(-S): ";
  h += s.worst < 0 ? "no target" : Millimetres(s.worst) + (std::isfinite(s.worst) ? " mm" : "");
  h += "</h2>";
  if (s.depth_only) h += "<p class=\"note\">No colour image in the dataset: the depth is shown.</p>";
  h += Printf("<div class=\"sec\"><div class=\"frame\"><img src=\"%s\" width=\"%d\" height=\"%d\" alt=\"%s\">", s.image_file.c_str(),
              s.width, s.height, EscapeXml(s.name).c_str());
  if (!s.boxes.empty()) h += BoxOverlay(s, dataset);
  h += "</div>";
  for (const Entry& e : s.entries) h += ObjectCard(e, in);
  return h + "</div>";
}

std::string WorstFirstTable(const std::vector<Section>& sections) {
  std::vector<std::pair<const Section*, const Entry*>> all;
  for (const Section& s : sections)
    for (const Entry& e : s.entries) all.push_back({&s, &e});
  std::stable_sort(all.begin(), all.end(),
                   [](const auto& a, const auto& b) { return SortError(*a.second) > SortError(*b.second); });
  const std::string header =
      "<table><tr><th>#</th><th class=\"l\">image</th><th class=\"l\">object</th><th>ADD(-S), mm</th>"
      "<th>ADD-S, mm</th><th>rotation</th><th>translation, mm</th><th class=\"l\">chosen box</th></tr>";
  std::string t = header;
  for (size_t rank = 0; rank < all.size(); ++rank) {
    const auto& [s, e] = all[rank];
    // The worst few stay in view; the rest fold away (a <details> element: no script).
    if (rank == kWorstShown)
      t += "</table><details><summary>all " + std::to_string(all.size()) + " objects</summary>" + header;
    const auto [css, word] = Verdict(*e);
    const bool scored = e->eval && e->eval->has_result;
    t += "<tr><td>" + std::to_string(rank + 1) + "</td><td class=\"l\"><a href=\"#img-" + s->stem + "\">" +
         EscapeXml(s->name) + "</a></td><td class=\"l\"><a href=\"#" + e->anchor + "\">" + Swatch(e->obj_id) +
         EscapeXml(e->name) + "</a></td><td class=\"" + css + "\">" +
         (e->eval ? (scored ? Millimetres(e->eval->add_or_adds_m) : "missed") : word) + "</td><td>" +
         Or(scored, Millimetres(scored ? e->eval->adds_m : 0)) + "</td><td>" +
         Or(scored, Printf("%.1f&deg;", scored ? e->eval->rotation_error_deg : 0)) + "</td><td>" +
         Or(scored, Printf("%.1f", scored ? e->eval->translation_error_mm : 0)) + "</td><td class=\"l\">" +
         (e->detail ? (e->chosen_is_distractor ? "<span class=\"fail\">distractor</span>" : "object") : "&ndash;") +
         "</td></tr>";
  }
  return t + (all.size() > kWorstShown ? "</table></details>" : "</table>");
}

std::string PageHtml(const Model& m) {
  const ReportInput& in = *m.input;
  int entries = 0, distractors = 0, chosen_distractors = 0;
  for (const Section& s : m.sections) {
    entries += static_cast<int>(s.entries.size());
    for (const Box& b : s.boxes) distractors += b.distractor, chosen_distractors += b.distractor && b.chosen;
  }
  std::string h = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>mcpose report</title><style>";
  h += kStyle;
  h += "</style></head><body>\n<h1>mcpose report</h1><ul>";
  h += "<li>dataset: <code>" + EscapeXml(m.dataset->root()) + "</code></li>";
  h += "<li>results: <code>" + EscapeXml(in.results_path) + "</code> (" + std::to_string(in.results.size()) +
       " rows)</li>";
  if (in.detections)
    h += "<li>detections: <code>" + EscapeXml(in.detections_path) + "</code> (" +
         std::to_string(in.detections->size()) + " boxes, " + std::to_string(distractors) + " distractors, " +
         std::to_string(chosen_distractors) + " of them chosen)</li>";
  if (in.detail) h += "<li>detail: <code>" + EscapeXml(in.detail_path) + "</code></li>";
  h += "<li>" + std::to_string(m.sections.size()) + " images, " + std::to_string(entries) +
       " objects; images and objects are ordered worst first (by ADD(-S); missed objects first)</li></ul>";
  h += "<p>On each image: an estimate's outline in its object's colour";
  if (in.draw_ground_truth) h += ", the ground truth's outline dashed white and black underneath";
  if (in.detections) h += "; boxes thin, the chosen box thick, distractors (over no visible pixel of their class) "
                          "dashed red";
  h += ". ADD(-S) uses ADD-S for the symmetric objects and ADD for the rest.</p>\n";
  h += "<h2 id=\"overview\">Accuracy</h2>" + AccuracyTable(m.eval);
  h += "<div class=\"plots\">" +
       CurvePlot(m.eval, "curve-adds", "ADD-S accuracy", in.eval.auc_max_m, &InstanceEval::adds_m) +
       CurvePlot(m.eval, "curve-add-s", "ADD(-S) accuracy", in.eval.auc_max_m, &InstanceEval::add_or_adds_m) +
       "</div>\n";
  h += "<h2 id=\"worst\">Objects, worst first</h2>" + WorstFirstTable(m.sections) + "\n";
  for (const Section& s : m.sections) h += SectionHtml(s, *m.dataset, in) + "\n";
  return h + "</body></html>\n";
}

int64_t FolderBytes(const fs::path& dir) {
  int64_t bytes = 0;
  for (const auto& f : fs::recursive_directory_iterator(dir))
    if (f.is_regular_file()) bytes += static_cast<int64_t>(f.file_size());
  return bytes;
}

// A report's folder holds this file: the list of the files the report wrote (paths relative to
// the folder, one a line). A later report replaces only a folder whose files are all listed.
constexpr char kMarker[] = ".mcpose-report";

// Ok if `out` can become the report folder: its parent exists, and it is absent, empty, or an
// earlier report holding nothing but what that report wrote.
Status CheckOutFolder(const fs::path& out) {
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(out, ec);
  if (!fs::exists(st)) return Status::Ok();
  if (fs::is_symlink(st)) return InvalidArgument(out.string() + ": is a link; a report is written to a real folder");
  if (!fs::is_directory(st)) return InvalidArgument(out.string() + ": exists and is not a folder");
  if (fs::is_empty(out, ec)) return Status::Ok();
  if (!fs::is_regular_file(fs::symlink_status(out / kMarker, ec)))
    return InvalidArgument(out.string() + ": exists, is not empty and is not a report of mcpose (no " +
                           std::string(kMarker) + " in it), so it is not replaced");
  MCPOSE_ASSIGN_OR_RETURN(std::string listed, io::ReadFileToString((out / kMarker).string()));
  std::set<std::string> ours;
  for (std::string_view line : io::SplitLines(listed))
    if (!line.empty()) ours.emplace(line);
  for (auto it = fs::recursive_directory_iterator(out, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    const std::string rel = fs::relative(it->path(), out, ec).string();
    const fs::file_status f = it->symlink_status(ec);
    const bool written = rel == kMarker || (fs::is_regular_file(f) && ours.contains(rel)) ||
                         (fs::is_directory(f) && rel == "images");
    if (!written)
      return InvalidArgument(out.string() + ": holds " + rel + ", which no report wrote, so it is not replaced");
  }
  if (ec) return Internal(out.string() + ": cannot list the folder (" + ec.message() + ")");
  return Status::Ok();
}

// Writes the marker of the report in `dir`: every regular file below it.
Status WriteMarker(const fs::path& dir) {
  std::vector<std::string> files;
  for (const auto& f : fs::recursive_directory_iterator(dir))
    if (f.is_regular_file()) files.push_back(fs::relative(f.path(), dir).string());
  std::sort(files.begin(), files.end());
  std::string text;
  for (const std::string& f : files) text += f + "\n";
  return io::WriteFileAtomic((dir / kMarker).string(), text);
}

Status WriteFolder(const Dataset& dataset, Model* m, const fs::path& tmp) {
  MeshCache meshes(dataset);
  for (Section& s : m->sections) MCPOSE_RETURN_IF_ERROR(DrawSection(dataset, *m->input, &meshes, tmp, &s));
  return io::WriteFileAtomic((tmp / "index.html").string(), PageHtml(*m));
}

}  // namespace

Rgba8 ObjectColour(int obj_id) {
  const size_t n = kPalette.size();
  return kPalette[(static_cast<size_t>(std::max(obj_id, 1)) - 1) % n];
}

std::string CssColour(Rgba8 c) { return Printf("#%02x%02x%02x", c.r, c.g, c.b); }

std::vector<std::array<double, 2>> AccuracyCurve(std::vector<double> errors_m, double max_m) {
  std::vector<std::array<double, 2>> points = {{0, 0}};
  if (errors_m.empty()) {
    points.push_back({max_m, 0});
    return points;
  }
  std::sort(errors_m.begin(), errors_m.end());
  const double n = static_cast<double>(errors_m.size());
  size_t below = 0;
  while (below < errors_m.size() && errors_m[below] < max_m) {
    // Errors equal to each other make one step.
    size_t next = below;
    while (next < errors_m.size() && errors_m[next] == errors_m[below]) ++next;
    points.push_back({errors_m[below], static_cast<double>(below) / n});
    points.push_back({errors_m[below], static_cast<double>(next) / n});
    below = next;
  }
  points.push_back({max_m, static_cast<double>(below) / n});
  return points;
}

bool IsDistractor(const Detection& box, std::span<const MaskImage> visible_masks) {
  for (const MaskImage& mask : visible_masks) {
    const render::PixelRect r = engine::ClipBox(box.x, box.y, box.w, box.h, mask.width, mask.height);
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x)
        if (mask.at(x, y)) return false;
  }
  return true;
}

StatusOr<ReportSummary> WriteReport(const Dataset& dataset, const ReportInput& input, const std::string& out_dir) {
  fs::path out = fs::path(out_dir).lexically_normal();
  if (out.filename().empty() && out.has_parent_path()) out = out.parent_path();  // "report/" names "report"
  std::error_code ec;
  const fs::path parent = out.has_parent_path() ? out.parent_path() : fs::path(".");
  if (!fs::is_directory(parent, ec)) return NotFound(out.string() + ": folder " + parent.string() + " does not exist");
  // One report into a folder at a time: two would each move the other's folder aside and away.
  MCPOSE_ASSIGN_OR_RETURN(const std::unique_ptr<io::FileLock> lock, io::FileLock::Acquire(out.string() + ".lock"));
  MCPOSE_RETURN_IF_ERROR(CheckOutFolder(out));
  MCPOSE_RETURN_IF_ERROR(CheckAgainstDataset(dataset, input));
  Model m;
  m.dataset = &dataset;
  m.input = &input;
  MCPOSE_ASSIGN_OR_RETURN(m.eval, Evaluate(dataset, input.results,
                                           input.detections ? &*input.detections : nullptr, input.eval));
  MCPOSE_RETURN_IF_ERROR(CollectSections(&m));

  // Everything goes into a new folder of its own beside the target, which takes the target's
  // place at the end; the earlier report (checked to hold only what a report wrote) goes then.
  MCPOSE_ASSIGN_OR_RETURN(const fs::path tmp, io::CreateFolderBeside(out.string(), ".tmp-"));
  Status status;
  if (!fs::create_directories(tmp / "images", ec))
    status = Internal(tmp.string() + ": cannot create the images folder: " + ec.message());
  if (status.ok()) status = WriteFolder(dataset, &m, tmp);
  if (status.ok()) status = WriteMarker(tmp);
  fs::path old;
  if (status.ok() && fs::exists(fs::symlink_status(out, ec))) {
    StatusOr<std::string> aside = io::CreateFolderBeside(out.string(), ".old-");
    if (!aside.ok())
      status = aside.status();
    else if (fs::rename(out, *aside, ec); ec)
      status = Internal(out.string() + ": cannot move the earlier report aside: " + ec.message());
    else
      old = *aside;
  }
  if (status.ok() && (fs::rename(tmp, out, ec), ec))
    status = Internal(out.string() + ": cannot move the report into place: " + ec.message());
  if (!status.ok()) {
    fs::remove_all(tmp, ec);
    if (!old.empty()) fs::rename(old, out, ec);
    return status;
  }
  if (!old.empty()) fs::remove_all(old, ec);

  ReportSummary summary;
  summary.images = static_cast<int>(m.sections.size());
  for (const Section& s : m.sections) {
    summary.objects += static_cast<int>(s.entries.size());
    for (const Box& b : s.boxes) summary.distractors += b.distractor;
  }
  summary.bytes = FolderBytes(out);
  return summary;
}

}  // namespace mcpose::report

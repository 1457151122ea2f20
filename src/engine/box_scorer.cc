#include "engine/box_scorer.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"
#include "engine/initialize.h"
#include "hw/rtl_core.h"
#include "score/weight.h"

namespace mcpose::engine {

render::PixelRect ClipBox(double x, double y, double w, double h, int width, int height) {
  render::PixelRect r;
  if (!(std::isfinite(x) && std::isfinite(y) && std::isfinite(w) && std::isfinite(h))) return r;
  // BOP boxes count pixel indices: [x, x + w) holds pixels x .. x + w - 1. Fractional
  // boxes are rounded outwards. Both ends are clamped to the image before the conversion to
  // int (a coordinate like 1e300 does not fit one).
  const auto clip = [](double v, int size) { return static_cast<int>(std::clamp(v, 0.0, static_cast<double>(size))); };
  r.x0 = clip(std::floor(x), width), r.x1 = clip(std::ceil(x + w), width);
  r.y0 = clip(std::floor(y), height), r.y1 = clip(std::ceil(y + h), height);
  if (r.empty()) return render::PixelRect{};
  return r;
}

}  // namespace mcpose::engine

namespace mcpose {

Status CheckBox(const Detection& d, const Intrinsics& K) {
  if (const std::string problem = CheckDetectionBox(d); !problem.empty()) return InvalidArgument(problem);
  if (engine::ClipBox(d.x, d.y, d.w, d.h, K.width, K.height).empty())
    return InvalidArgument("box " + BoxText(d) + " lies outside the " + std::to_string(K.width) + "x" +
                           std::to_string(K.height) + " image");
  return Status::Ok();
}

}  // namespace mcpose

namespace mcpose::engine {

int BoxStride(const render::PixelRect& rect, const EngineOptions& options) {
  int s = std::max(1, options.pixel_stride);
  if (options.max_grid_pixels <= 0) return s;
  auto grid = [&](int k) { return int64_t{(rect.width() + k - 1) / k} * ((rect.height() + k - 1) / k); };
  while (grid(s) > options.max_grid_pixels && s < 16) ++s;
  return s;
}

StatusOr<std::unique_ptr<BoxScorer>> BoxScorer::Create(Context& context, const Intrinsics& K,
                                                       const DepthImage& depth, const Mesh& mesh,
                                                       std::span<const Detection> boxes,
                                                       const ColourImage* colour, Resolution resolution) {
  const EstimatorOptions& opt = context.options();
  // ---- Validate the inputs at the boundary ---------------------------------------------
  std::string error;
  if (!K.IsValid(&error)) return InvalidArgument(error);
  if (depth.width != K.width || depth.height != K.height ||
      depth.depth_m.size() != static_cast<size_t>(depth.width) * depth.height) {
    return InvalidArgument("depth image is " + std::to_string(depth.width) + "x" + std::to_string(depth.height) +
                           " but the intrinsics say " + std::to_string(K.width) + "x" + std::to_string(K.height));
  }
  if (colour && (colour->width != depth.width || colour->height != depth.height ||
                 colour->rgba.size() != 4 * static_cast<size_t>(depth.width) * depth.height)) {
    return InvalidArgument("colour image is " + std::to_string(colour->width) + "x" + std::to_string(colour->height) +
                           " but the depth image is " + std::to_string(depth.width) + "x" + std::to_string(depth.height));
  }
  MCPOSE_RETURN_IF_ERROR(mesh.Validate("mesh"));
  if (boxes.empty()) return InvalidArgument("no boxes given");
  for (size_t b = 0; b < boxes.size(); ++b) {
    const std::string where = "box " + std::to_string(b) + " of obj_id " + std::to_string(boxes[0].obj_id) + ": ";
    if (boxes[b].obj_id != boxes[0].obj_id) return InvalidArgument(where + "boxes of different classes given");
    if (Status s = CheckBox(boxes[b], K); !s.ok()) return InvalidArgument(where + s.message());
  }

  std::unique_ptr<BoxScorer> scorer(new BoxScorer(context));
  BoxScorer& s = *scorer;
  s.K_ = K;
  s.mesh_ = &mesh;
  s.detections_.assign(boxes.begin(), boxes.end());
  // ---- The colour term: the model's colour grid, when there is colour on both sides -------
  if (colour) s.colour_ = context.Colour(mesh);
  if (s.colour_) s.colour_lookup_ = s.colour_->lookup(opt.appearance.space);
  uint32_t (*transform)(uint32_t) = opt.appearance.space == AppearanceOptions::Space::kChroma ? score::ChromaOf
                                    : opt.appearance.space == AppearanceOptions::Space::kIntensityHue
                                        ? score::IntensityHueOf
                                        : nullptr;
  // ---- Depth distributor: each box's observation, cut out once ---------------------------
  for (const Detection& d : boxes) {
    const render::PixelRect rect = ClipBox(d.x, d.y, d.w, d.h, K.width, K.height);
    const int stride = resolution == Resolution::kFull ? 1 : BoxStride(rect, opt.engine);
    s.observed_.push_back(score::DistributeBox(depth, K, rect, d.score, opt.weight.inlier, stride,
                                               s.colour_ ? colour : nullptr, transform,
                                               opt.appearance.smooth_radius, opt.appearance.drop_clipped));
    if (IsHardwareNumerics(opt.engine.backend))
      score::AddDepthBounds(&s.observed_.back(), static_cast<float>(opt.weight.eps_m));
  }
  // ---- Level of detail: per box, the coarsest mesh within the pixel error budget ----------
  if (resolution == Resolution::kEngine) s.lod_ = context.Lod(mesh);
  for (size_t b = 0; b < boxes.size(); ++b) {
    backends::BoxTarget target{&s.observed_[b], &mesh, nullptr, s.colour_ ? &s.colour_lookup_ : nullptr};
    const render::LodLevel* level = nullptr;
    if (s.lod_) {
      level = &s.lod_->level(SelectLodLevel(*s.lod_, K, mesh, boxes[b], s.observed_[b], opt));
      target.mesh = &level->mesh;
      if (opt.engine.cluster_culling) target.clusters = &level->clusters;
    }
    s.levels_.push_back(level);
    s.targets_.push_back(target);
  }
  // ---- The hardware's formats of each distinct mesh (engine backends hw and rtl) -----------
  if (IsHardwareNumerics(opt.engine.backend)) {
    for (backends::BoxTarget& target : s.targets_) {
      auto it = std::find_if(s.hw_models_.begin(), s.hw_models_.end(),
                             [&](const auto& m) { return m.first == target.mesh; });
      if (it == s.hw_models_.end()) {
        auto quantized = std::make_unique<std::vector<hw::ModelVertex>>();
        if (!hw::QuantizeModel(target.mesh->vertices_m, quantized.get()))
          return InvalidArgument("mesh: a vertex more than 0.8192 m from the model's origin, beyond the range of "
                                 "engine backend hw (model coordinates: 16 bits of 25 um)");
        s.hw_models_.emplace_back(target.mesh, std::move(quantized));
        it = std::prev(s.hw_models_.end());
      }
      target.hw_model = it->second.get();
    }
  }
  // The simulated core's memories (hw/rtl_core.h).
  if (opt.engine.backend == RasterBackend::kRtl) {
    for (const backends::BoxTarget& target : s.targets_) {
      const render::PixelRect& r = target.observed->rect;
      if (r.width() > hw::kRtlMaxBoxSide || r.height() > hw::kRtlMaxBoxSide ||
          r.area() > (int64_t{1} << hw::kRtlBoxWordBits))
        return InvalidArgument("engine backend rtl: a box of " + std::to_string(r.width()) + " x " +
                               std::to_string(r.height()) + " grid pixels, beyond the simulated core's memories (" +
                               std::to_string(1 << hw::kRtlBoxWordBits) + " pixels, " +
                               std::to_string(hw::kRtlMaxBoxSide) + " a side)");
      if (target.mesh->vertices_m.size() > (size_t{1} << hw::kRtlVertexIndexBits))
        return InvalidArgument("engine backend rtl: a mesh of " + std::to_string(target.mesh->vertices_m.size()) +
                               " vertices, beyond the simulated core's vertex memory (" +
                               std::to_string(1 << hw::kRtlVertexIndexBits) + ")");
    }
  }
  s.depth_ = &depth;
  if (resolution == Resolution::kEngine) s.rests_ = context.Rests(mesh);
  s.extremes_ = context.Extremes(mesh);
  if (s.extremes_)
    for (const Detection& d : boxes) s.fit_boxes_.push_back(score::FitBoxOf(d, K));
  s.settings_.inlier_mode = opt.weight.inlier;
  s.settings_.eps_m = static_cast<float>(opt.weight.eps_m);
  s.settings_.cull_backfaces = opt.engine.backface_culling;
  s.settings_.batched_setup = opt.engine.batched_setup;
  s.settings_.colour_step = opt.appearance.pixel_step;
  return scorer;
}

void BoxScorer::set_inlier_threshold(float eps_m) {
  settings_.eps_m = eps_m;
  if (IsHardwareNumerics(context_->options().engine.backend))
    for (score::BoxObservation& o : observed_) score::AddDepthBounds(&o, eps_m);
}

int64_t BoxScorer::depth_pixels_read() const {
  render::PixelRect u = observed_[0].image_rect;
  for (const score::BoxObservation& b : observed_) {
    const auto& r = b.image_rect;
    u.x0 = std::min(u.x0, r.x0), u.y0 = std::min(u.y0, r.y0), u.x1 = std::max(u.x1, r.x1), u.y1 = std::max(u.y1, r.y1);
  }
  std::vector<char> covered(static_cast<size_t>(u.area()), 0);
  for (const score::BoxObservation& b : observed_) {
    const auto& r = b.image_rect;
    for (int y = r.y0; y < r.y1; y += b.stride)
      for (int x = r.x0; x < r.x1; x += b.stride) covered[static_cast<size_t>(y - u.y0) * u.width() + (x - u.x0)] = 1;
  }
  return std::count(covered.begin(), covered.end(), 1);
}

void BoxScorer::Count(const filter::ParticleSet& particles, std::span<score::InlierCounts> counts,
                      EngineCounters* counters) {
  RasterCounters stats;
  context_->cores().Score(targets_, settings_, particles, counts, &stats);
  counters->triangles_full += static_cast<int64_t>(mesh_->triangles.size()) * static_cast<int64_t>(particles.size());
  *counters += stats;
}

void BoxScorer::Weigh(filter::ParticleSet* particles, EngineCounters* counters, double colour_weight) {
  filter::ParticleSet& p = *particles;
  counts_.resize(p.size());
  Count(p, counts_, counters);
  const WeightOptions& w = context_->options().weight;
  if (!colour_) {
    for (size_t i = 0; i < p.size(); ++i) p.weight[i] = score::Weight(counts_[i], observed_[p.box[i]].score, w);
  } else {
    AppearanceOptions a = context_->options().appearance;
    if (colour_weight >= 0) a.weight = colour_weight;
    for (size_t i = 0; i < p.size(); ++i)
      p.weight[i] = score::WeightWithColour(counts_[i], observed_[p.box[i]].score, w, a);
  }
  if (extremes_) {
    for (size_t i = 0; i < p.size(); ++i) {
      const double share = score::BoxFitShare(*extremes_, p.R_cam_obj[i], p.t_cam_obj_m[i], K_,
                                              fit_boxes_[static_cast<size_t>(p.box[i])]);
      p.weight[i] *= score::BoxFitFactor(share, w.box_fit);
    }
  }
}

}  // namespace mcpose::engine

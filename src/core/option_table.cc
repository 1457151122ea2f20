#include "mcpose/option_table.h"

#include "mcpose/tracker.h"

#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <type_traits>
#include <vector>

#include <hwy/targets.h>

namespace mcpose {

namespace {

constexpr std::array<const char*, 2> kInlierNames = {"1d", "3d"};                        // InlierMode
constexpr std::array<const char*, 6> kBackendNames = {"scalar", "fixed", "simd", "float-simd", "hw", "rtl"};  // RasterBackend
constexpr std::array<const char*, 3> kSpaceNames = {"rgb", "chroma", "intensity-hue"};  // Space
constexpr std::array<const char*, 2> kOnOff = {"off", "on"};

// "best", then the Highway targets this build compiled, best first (SimdTarget).
const std::vector<const char*>& SimdNames() {
  static const std::vector<const char*> names = [] {
    std::vector<const char*> n = {"best"};
    for (int64_t bits = HWY_TARGETS; bits != 0; bits &= bits - 1) n.push_back(hwy::TargetName(bits & -bits));
    return n;
  }();
  return names;
}

template <class T>
constexpr OptionType TypeOf() {
  if constexpr (std::is_same_v<T, bool>) return OptionType::kBool;
  else if constexpr (std::is_same_v<T, uint64_t>) return OptionType::kSeed;
  else if constexpr (std::is_same_v<T, int>) return OptionType::kInt;
  else if constexpr (std::is_same_v<T, double>) return OptionType::kDouble;
  else {
    static_assert(std::is_enum_v<T> && std::is_same_v<std::underlying_type_t<T>, int>, "an option's type");
    return OptionType::kEnum;
  }
}

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kIntMax = std::numeric_limits<int>::max();
using Sw = OptionField::Switch;

// The key, flag, type and address of field `member` of EstimatorOptions.
#define MCPOSE_OPTION(member, flag)                                                          \
  #member, flag, TypeOf<std::remove_cvref_t<decltype(std::declval<EstimatorOptions&>().member)>>(), \
      [](EstimatorOptions& o) -> void* { return &o.member; }

// Field, flag; bounds (min, max, min_open, max_open); unit; doc; group; switch style; enum names.
const OptionField kFields[] = {
    {MCPOSE_OPTION(samples, "--samples"), 1, limits::kMaxSamples, false, false, "",
     "Samples per object class per image, over all its boxes", kSamplingOptions},
    {MCPOSE_OPTION(seed, "--seed"), 0, 0, false, false, "",
     "Random seed; same seed, same results at any thread count", kSamplingOptions},
    {MCPOSE_OPTION(max_instances, "--max-instances"), 0, limits::kMaxBoxesPerImage, false, false, "",
     "Instances of one class an image may hold; 0: as many as its boxes show, 1: one pose per class",
     kInstanceOptions},
    {MCPOSE_OPTION(max_iterations, "--iterations"), 1, limits::kMaxIterations, false, false, "", "Iteration limit",
     kStoppingOptions},
    {MCPOSE_OPTION(tau, "--tau"), -kInf, kInf, false, false, "", "Stop when the mean weight exceeds tau",
     kStoppingOptions},

    {MCPOSE_OPTION(weight.inlier, "--inlier"), 0, 0, false, false, "",
     "Inlier test: 1d (|z_r - z_o| < eps) or 3d (nearest observed point)", kWeightOptions, Sw::kPair, kInlierNames},
    {MCPOSE_OPTION(weight.eps_m, "--eps"), 0, kInf, true, false, "m", "Inlier threshold, metres", kWeightOptions},
    {MCPOSE_OPTION(weight.a, nullptr), 0, 1, false, false, "", "a in w = a N/N_b + b N/N_r + c score (--weights)",
     kWeightOptions},
    {MCPOSE_OPTION(weight.b, nullptr), 0, 1, false, false, "", "b (--weights)", kWeightOptions},
    {MCPOSE_OPTION(weight.c, nullptr), 0, 1, false, false, "", "c (--weights)", kWeightOptions},
    {MCPOSE_OPTION(weight.occlusion_aware, "--occlusion-aware"), 0, 0, false, false, "",
     "Leave rendered pixels hidden behind observed surfaces out of N_r (off: the paper's N_r)", kWeightOptions},
    {MCPOSE_OPTION(weight.box_fit, "--box-fit"), 0, 1, false, false, "",
     "A sample whose projected object lies less than this share inside its box has its weight scaled by share / "
     "box-fit; 0: off",
     kWeightOptions},

    {MCPOSE_OPTION(init.sigma_t_m, "--init-sigma-t"), 0, limits::kMaxSigmaM, false, false, "m",
     "Initial translation jitter, metres", kSearchOptions},
    {MCPOSE_OPTION(init.front_share, "--init-front-share"), 0, 1, false, false, "",
     "Share of each box's samples whose turned model starts with its nearest point at --init-front-quantile of the "
     "box's valid depths; the rest start with the model's origin at --init-depth-quantile plus half its median side",
     kSearchOptions},
    {MCPOSE_OPTION(init.rest_share, "--init-rest-share"), 0, 1, false, false, "",
     "Share of each box's samples that start at rest on the plane the box stands on (a stable face of the model "
     "down, turned at random about the plane's normal), taken from the samples not at the front first",
     kSearchOptions},
    {MCPOSE_OPTION(init.rest_spread, "--init-rest-spread"), 0, 1, false, false, "",
     "Rest samples stand on rays through random points of this central share of their box (in width and height); "
     "0: the ray through the box centre",
     kSearchOptions},
    {MCPOSE_OPTION(init.wide, "--init-wide"), 1, limits::kMaxInitWide, false, false, "",
     "The first generation holds this many times --samples samples, weighed once; 1: the paper's", kSearchOptions},
    {MCPOSE_OPTION(init.front_quantile, "--init-front-quantile"), 0, 1, false, false, "",
     "Quantile of the box's valid depths where a front sample's nearest point starts", kSearchOptions},
    {MCPOSE_OPTION(init.depth_quantile, "--init-depth-quantile"), 0, 1, false, false, "",
     "Quantile of the box's valid depths for the other samples and the level of detail", kSearchOptions},
    {MCPOSE_OPTION(resample.keep_top_fraction, "--keep-top"), 0, 1, true, false, "",
     "Resample from this best fraction of samples", kSearchOptions},
    {MCPOSE_OPTION(resample.elite_share, "--elite"), 0, 1, false, false, "",
     "The best share of the samples (at most --keep-top) passes to the next generation as it is, not drawn or "
     "diffused; 0: the paper's resampling",
     kSearchOptions},
    {MCPOSE_OPTION(resample.cdf_table_size, "--cdf-table"), 1, limits::kMaxCdfTable, false, false, "",
     "Entries of the coarse CDF threshold table", kSearchOptions},
    {MCPOSE_OPTION(diffusion.sigma_t_m, "--sigma-t"), 0, limits::kMaxSigmaM, false, false, "m",
     "Diffusion: translation sigma at iteration 0, metres", kSearchOptions},
    {MCPOSE_OPTION(diffusion.sigma_r_rad, "--sigma-r"), 0, limits::kMaxSigmaRad, false, false, "rad",
     "Diffusion: rotation sigma at iteration 0, radians", kSearchOptions},
    {MCPOSE_OPTION(diffusion.sigma_t_min_m, "--sigma-t-min"), 0, limits::kMaxSigmaM, false, false, "m",
     "Diffusion: smallest translation sigma, metres", kSearchOptions},
    {MCPOSE_OPTION(diffusion.sigma_r_min_rad, "--sigma-r-min"), 0, limits::kMaxSigmaRad, false, false, "rad",
     "Diffusion: smallest rotation sigma, radians", kSearchOptions},
    {MCPOSE_OPTION(diffusion.anneal, "--anneal"), 0, 1, true, false, "", "Diffusion: sigma factor per iteration",
     kSearchOptions},
    {MCPOSE_OPTION(diffusion.flip_rate, "--flip-rate"), 0, 1, false, false, "",
     "Diffusion: probability that a resampled sample turns 180 degrees about a model axis", kSearchOptions},

    {MCPOSE_OPTION(appearance.enabled, "--appearance"), 0, 0, false, false, "",
     "Colour: on (a colour term in the weight wherever the model and the frame have colour) or off (depth only)",
     kAppearanceOptions, Sw::kOnOff},
    {MCPOSE_OPTION(appearance.weight, "--colour-weight"), 0, 1, false, true, "",
     "d in w = (1 - d) w_depth + d A, A the colour agreement of the depth inliers", kAppearanceOptions},
    {MCPOSE_OPTION(appearance.space, "--colour-space"), 0, 0, false, false, "",
     "What the colour term compares: intensity-hue (intensity and normalised colour), chroma (normalised colour, "
     "which shading does not change) or rgb",
     kAppearanceOptions, Sw::kPair, kSpaceNames},
    {MCPOSE_OPTION(appearance.resolve_twins, "--resolve-twins"), 0, 0, false, false, "",
     "After the filter, score the best pose's depth twins on every pixel with colour and refine the best",
     kAppearanceOptions},
    {MCPOSE_OPTION(appearance.twin_depth_margin, "--twin-depth-margin"), 0, 1, false, false, "",
     "Twin candidates within this of the best depth weight are told apart by colour alone; 0: by the whole weight",
     kAppearanceOptions},
    {MCPOSE_OPTION(appearance.twin_step_deg, "--twin-step"), 1, 180, false, false, "deg",
     "Twin candidates: turns about the model's most distinct axis in these steps, degrees (divides 360)",
     kAppearanceOptions},
    {MCPOSE_OPTION(appearance.twin_refine_iterations, "--twin-refine"), 0, limits::kMaxIterations, false, false, "",
     "Iterations of the filter that refine the chosen twin", kAppearanceOptions},
    {MCPOSE_OPTION(appearance.ramp_iterations, "--colour-ramp"), 0, limits::kMaxIterations, false, false, "",
     "The colour term's weight grows over this many first iterations; 0: full from the start", kAppearanceOptions},
    {MCPOSE_OPTION(appearance.pixel_step, "--colour-step"), 1, 4, false, false, "",
     "The colour test reads every n-th pixel of each box's grid in x and y", kAppearanceOptions},
    {MCPOSE_OPTION(appearance.hue_first_levels, "--colour-hue-first"), 0, 255, false, false, "levels",
     "Intensity-hue: where the model's hue varies by at least this standard deviation, hue alone decides (shading "
     "does not change it), elsewhere intensity alone; 0: both together",
     kAppearanceOptions},
    {MCPOSE_OPTION(appearance.smooth_radius, "--colour-smooth"), 0, 3, false, false, "",
     "Each observed colour tested is the mean of the (2 r + 1)^2 pixels around it; 0: the pixel alone",
     kAppearanceOptions},
    {MCPOSE_OPTION(appearance.drop_clipped, "--colour-drop-clipped"), 0, 0, false, false, "",
     "Leave out observed pixels with a clipped channel (at 255, or at a level many of the box's pixels share)",
     kAppearanceOptions},
    {MCPOSE_OPTION(appearance.trust_pixels, "--colour-trust-pixels"), 0, 1e6, false, false, "pixels",
     "Colour seen on n pixels counts n / (n + this) of its full say; 0: full say from --colour-min-pixels on",
     kAppearanceOptions},
    {MCPOSE_OPTION(appearance.min_pixels, "--colour-min-pixels"), 2, kIntMax, false, false, "pixels",
     "Fewer depth inliers of known colour than this: the neutral A = 0.5", kAppearanceOptions},

    {MCPOSE_OPTION(refine.enabled, "--refine"), 0, 0, false, false, "",
     "Align the final pose to the observed depth (point-to-plane, robust), kept if its weight does not drop",
     kRefineOptions, Sw::kOnOff},
    {MCPOSE_OPTION(refine.max_iterations, "--refine-iterations"), 0, limits::kMaxIterations, false, false, "",
     "Alignment steps for the final pose", kRefineOptions},
    {MCPOSE_OPTION(refine.twin_iterations, "--refine-twin-iterations"), 0, limits::kMaxIterations, false, false, "",
     "Alignment steps for each twin candidate", kRefineOptions},
    {MCPOSE_OPTION(refine.tukey_m, "--refine-tukey"), 0, kInf, true, false, "m",
     "Robust (Tukey) loss scale of the alignment, metres", kRefineOptions},
    {MCPOSE_OPTION(refine.max_distance_m, "--refine-max-distance"), 0, kInf, true, false, "m",
     "The alignment pairs no model and observed points farther apart than this, metres", kRefineOptions},
    {MCPOSE_OPTION(refine.accept_eps_m, "--refine-accept-eps"), 0, kInf, false, false, "m",
     "Inlier threshold (m) of the weight that decides whether the aligned pose is kept; 0: --eps", kRefineOptions},

    {MCPOSE_OPTION(engine.backend, "--engine"), 0, 0, false, false, "",
     "Raster core: scalar (float reference), float-simd (the reference a vector at a time, same results), fixed "
     "(1/16-pixel fixed point), simd (fixed point a vector at a time) hw (the paper's hardware raster core "
     "in its integer numerics, docs/hardware.md; 1-D inliers) or rtl (that core's RTL simulated by Verilator: hw's "
     "results, some 150 times slower; builds with Verilator only)",
     kEngineOptions, Sw::kPair, kBackendNames},
    {MCPOSE_OPTION(engine.threads, "--threads"), 0, limits::kMaxThreads, false, false, "",
     "Worker threads; 0 = all hardware threads", kEngineOptions},
    {MCPOSE_OPTION(engine.simd_target, "--simd-target"), 0, 0, false, false, "",
     "Cap this estimator's SIMD dispatch at this Highway target (one this CPU has, e.g. AVX2 on an AVX-512 "
     "machine); best: the best it has; the same results on every target",
     kEngineOptions, Sw::kPair, SimdNames()},
    {MCPOSE_OPTION(engine.pixel_stride, "--pixel-stride"), 1, 16, false, false, "px",
     "Score every s-th pixel in x and y of each box; 1 with --max-grid-pixels 0 = every pixel", kEngineOptions},
    {MCPOSE_OPTION(engine.max_grid_pixels, "--max-grid-pixels"), 0, kIntMax, false, false, "pixels",
     "Score a box with more grid pixels than this at a coarser stride; 0 = no budget", kEngineOptions},
    {MCPOSE_OPTION(engine.lod_error_px, "--lod-px"), 0, kInf, false, false, "px",
     "Level of detail: the coarsest simplified mesh within this many image pixels of the full mesh at the box's "
     "depth; 0 = full mesh",
     kEngineOptions},
    {MCPOSE_OPTION(engine.lod_unbiased, "--lod-unbiased"), 0, 0, false, false, "",
     "LOD levels' vertices moved so that the full surface lies on each level on average (with LOD)",
     kEngineOptions},
    {MCPOSE_OPTION(engine.backface_culling, "--backface-culling"), 0, 0, false, false, "",
     "Cull back-facing triangles", kEngineOptions},
    {MCPOSE_OPTION(engine.cluster_culling, "--cluster-culling"), 0, 0, false, false, "",
     "Drop whole triangle clusters outside the box or facing away before setup (with LOD, on the fixed and simd "
     "engines)",
     kEngineOptions},
    {MCPOSE_OPTION(engine.batched_setup, "--batched-setup"), 0, 0, false, false, "",
     "Decide and set up triangles a SIMD vector at a time, same results (on the fixed and simd engines)",
     kEngineOptions},
};

#undef MCPOSE_OPTION

// The key, flag, type and address of field `member` of TrackerOptions.
#define MCPOSE_TRACKER_OPTION(member, flag)                                                       \
  #member, flag, TypeOf<std::remove_cvref_t<decltype(std::declval<TrackerOptions&>().member)>>(), \
      [](TrackerOptions& o) -> void* { return &o.member; }

const TrackerOptionField kTrackerFields[] = {
    {MCPOSE_TRACKER_OPTION(samples, "--track-samples"), 1, limits::kMaxSamples, false, false, "",
     "Samples of a tracked frame", kTrackerOptions},
    {MCPOSE_TRACKER_OPTION(iterations, "--track-iterations"), 1, limits::kMaxIterations, false, false, "",
     "Filter iterations of a tracked frame", kTrackerOptions},
    {MCPOSE_TRACKER_OPTION(stop_weight, "--stop-weight"), -kInf, kInf, false, false, "",
     "A tracked frame stops when its mean weight exceeds this", kTrackerOptions},
    {MCPOSE_TRACKER_OPTION(motion_sigma_t_m, "--motion-sigma-t"), 0, limits::kMaxSigmaM, false, false, "m",
     "Motion model: translation noise per frame, metres", kTrackerOptions},
    {MCPOSE_TRACKER_OPTION(motion_sigma_r_rad, "--motion-sigma-r"), 0, limits::kMaxSigmaRad, false, false, "rad",
     "Motion model: rotation noise per frame, radians", kTrackerOptions},
    {MCPOSE_TRACKER_OPTION(box_margin, "--box-margin"), 0, 2, false, false, "",
     "A tracked frame's box: the last silhouette grown by this fraction a side", kTrackerOptions},
    {MCPOSE_TRACKER_OPTION(refine_iterations, "--track-refine-iterations"), 0, limits::kMaxIterations, false, false,
     "", "Refinement steps in a tracked frame (0: none)", kTrackerOptions},
    {MCPOSE_TRACKER_OPTION(lost_fit, "--lost-fit"), 0, 1, false, false, "",
     "The track is lost where the share of the answer's visible silhouette that the depth confirms is below this",
     kTrackerOptions},
    {MCPOSE_TRACKER_OPTION(lost_visible, "--lost-visible"), 0, 1, false, false, "",
     "The track is lost where the share of the answer's silhouette not hidden behind nearer surfaces is below this",
     kTrackerOptions},
};

#undef MCPOSE_TRACKER_OPTION

// Shortest decimal text that reads back to the same double ("0.01", "620", "1e-06").
std::string DoubleText(double v) {
  char buf[64];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return ec == std::errc() ? std::string(buf, end) : std::string("nan");
}

std::string BoundText(double v) {
  if (std::isinf(v)) return v < 0 ? "-inf" : "inf";
  if (v == std::floor(v) && std::fabs(v) < 1e15) return std::to_string(static_cast<long long>(v));  // 1000000
  return DoubleText(v);
}

}  // namespace

std::span<const OptionField> EstimatorOptionFields() { return kFields; }

const OptionField* FindOptionField(const std::string& key) {
  for (const OptionField& f : kFields)
    if (key == f.key) return &f;
  return nullptr;
}

std::span<const TrackerOptionField> TrackerOptionFields() { return kTrackerFields; }

const TrackerOptionField* FindTrackerOptionField(const std::string& key) {
  for (const TrackerOptionField& f : kTrackerFields)
    if (key == f.key) return &f;
  return nullptr;
}

std::span<const char* const> InlierModeNames() { return kInlierNames; }
std::span<const char* const> RasterBackendNames() { return kBackendNames; }
std::span<const char* const> ColourSpaceNames() { return kSpaceNames; }
std::span<const char* const> SimdTargetNames() { return SimdNames(); }

std::string ChoicesText(std::span<const char* const> names) {
  std::string s;
  for (size_t i = 0; i < names.size(); ++i) s += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + std::string(names[i]);
  return s;
}

namespace {

template <class Options>
std::string MarkdownRows(std::span<const BasicOptionField<Options>> fields, const Options& defaults) {
  using Field = BasicOptionField<Options>;
  std::string md = "| flag | JSON key | default | values | unit | meaning |\n|---|---|---|---|---|---|\n";
  for (const Field& f : fields) {
    std::string flag = f.flag ? std::string("`") + f.flag + "`" : "`--weights a b c`";
    if (f.flag && f.type == Field::Type::kBool && f.style == Field::Switch::kPair)
      flag = std::string("`--[no-]") + (f.flag + 2) + "`";
    std::string doc = f.doc;
    for (size_t i = 0; (i = doc.find('|', i)) != std::string::npos; i += 2) doc.replace(i, 1, "\\|");
    md += "| " + flag + " | `" + f.key + "` | " + f.Text(defaults) + " | " + f.BoundsText() + " | " + f.unit +
          " | " + doc + " |\n";
  }
  return md;
}

}  // namespace

std::string OptionTableMarkdown() { return MarkdownRows(EstimatorOptionFields(), EstimatorOptions{}); }

std::string TrackerOptionTableMarkdown() { return MarkdownRows(TrackerOptionFields(), TrackerOptions{}); }

template <class Options>
std::string BasicOptionField<Options>::Text(const Options& options) const {
  switch (type) {
    case Type::kInt: return std::to_string(this->template Get<int>(options));
    case Type::kSeed: return std::to_string(this->template Get<uint64_t>(options));
    case Type::kDouble: return DoubleText(this->template Get<double>(options));
    case Type::kBool: return kOnOff[this->template Get<bool>(options) ? 1 : 0];
    case Type::kEnum: {
      const int v = this->template Get<int>(options);
      return v >= 0 && static_cast<size_t>(v) < names.size() ? names[static_cast<size_t>(v)] : "unknown";
    }
  }
  return "";
}

template <class Options>
bool BasicOptionField<Options>::Parse(const std::string& text, Options* options) const {
  if (type == Type::kBool) {
    if (text != "on" && text != "off") return false;
    this->template Ref<bool>(*options) = text == "on";
    return true;
  }
  if (type == Type::kEnum)
    for (size_t i = 0; i < names.size(); ++i)
      if (text == names[i]) {
        this->template Ref<int>(*options) = static_cast<int>(i);
        return true;
      }
  return false;
}

template <class Options>
std::string BasicOptionField<Options>::BoundsText() const {
  if (type == Type::kBool) return "on, off";
  if (type == Type::kEnum) return ChoicesText(names);
  if (type == Type::kSeed) return "[0, 2^64 - 1]";
  if (std::isinf(min) && std::isinf(max)) return "finite";
  if (std::isinf(max)) return std::string(min_open ? "> " : ">= ") + BoundText(min);
  return std::string(min_open ? "(" : "[") + BoundText(min) + ", " + BoundText(max) + (max_open ? ")" : "]");
}

template <class Options>
std::string BasicOptionField<Options>::CheckBounds(const Options& options) const {
  if (type != Type::kInt && type != Type::kDouble) return "";
  const double v = type == Type::kInt ? static_cast<double>(this->template Get<int>(options)) : this->template Get<double>(options);
  const bool ok = std::isfinite(v) && (min_open ? v > min : v >= min) && (max_open ? v < max : v <= max);
  if (ok) return "";
  const std::string unit_text = *unit && std::string(unit) != "pixels" ? std::string(" ") + unit : "";
  const std::string bounds = BoundsText();
  const std::string rule = bounds == "finite" ? "must be finite"
                           : bounds[0] == '>' ? "must be finite and " + bounds
                                              : "must lie in " + bounds;
  return std::string(key) + " " + rule + unit_text + ", got " + Text(options);
}

template struct BasicOptionField<EstimatorOptions>;
template struct BasicOptionField<TrackerOptions>;

}  // namespace mcpose

#include "cli/common.h"

#include <charconv>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "core/physical_limits.h"
#include "io/io_util.h"
#include "render/simd_targets.h"

namespace mcpose::cli {

void AddEstimatorFlags(CLI::App* cmd, unsigned groups, EstimatorFlags* f) {
  EstimatorOptions& o = f->options;
  if (groups & kSamplingFlags) {
    cmd->add_option("--samples", o.samples, "Samples per object class per image")->capture_default_str();
    cmd->add_option("--seed", o.seed, "Random seed; same seed, same results at any thread count")
        ->check(SeedCheck())
        ->capture_default_str();
  }
  if (groups & kInstanceFlags)
    cmd->add_option("--max-instances", o.max_instances,
                    "Instances of one class an image may hold; 0: as many as its boxes show, 1: one pose per class")
        ->capture_default_str();
  if (groups & kStoppingFlags) {
    cmd->add_option("--iterations", o.max_iterations, "Iteration limit")->capture_default_str();
    cmd->add_option("--tau", o.tau, "Stop when the mean weight exceeds tau")->capture_default_str();
  }
  if (groups & kWeightFlags) {
    cmd->add_option("--inlier", f->inlier, "Inlier test: 1d (|z_r - z_o| < eps) or 3d (nearest observed point)")
        ->capture_default_str();
    cmd->add_option("--eps", o.weight.eps_m, "Inlier threshold, metres")->capture_default_str();
    char help[128];
    std::snprintf(help, sizeof help,
                  "Weight coefficients a b c (sum 1): w = a N/N_b + b N/N_r + c score (default %.2f %.2f %.2f)",
                  o.weight.a, o.weight.b, o.weight.c);
    cmd->add_option("--weights", f->weights, help)->expected(3);
    cmd->add_flag("--occlusion-aware,!--no-occlusion-aware", o.weight.occlusion_aware,
                  "Leave rendered pixels hidden behind observed surfaces out of N_r (default on; off: the paper's N_r)");
    cmd->add_option("--box-fit", o.weight.box_fit,
                    "A sample whose projected object lies less than this share inside its box has its weight scaled "
                    "by share / box-fit; 0: off")
        ->capture_default_str();
  }
  if (groups & kSearchFlags) {
    cmd->add_option("--init-sigma-t", o.init.sigma_t_m, "Initial translation jitter, metres")->capture_default_str();
    cmd->add_option("--init-front-share", o.init.front_share,
                    "Share of each box's samples whose turned model starts with its nearest point at "
                    "--init-front-quantile of the box's valid depths; the rest start with the model's origin at "
                    "--init-depth-quantile plus half its median side; [0, 1]")
        ->capture_default_str();
    cmd->add_option("--init-rest-share", o.init.rest_share,
                    "Share of each box's samples that start at rest on the plane the box stands on (a stable face "
                    "of the model down, turned at random about the plane's normal), taken from the samples not at "
                    "the front first; [0, 1]")
        ->capture_default_str();
    cmd->add_option("--init-front-quantile", o.init.front_quantile,
                    "Quantile of the box's valid depths where a front sample's nearest point starts")
        ->capture_default_str();
    cmd->add_option("--init-depth-quantile", o.init.depth_quantile,
                    "Quantile of the box's valid depths for the other samples and the level of detail")
        ->capture_default_str();
    cmd->add_option("--keep-top", o.resample.keep_top_fraction, "Resample from this best fraction of samples, (0, 1]")
        ->capture_default_str();
    cmd->add_option("--cdf-table", o.resample.cdf_table_size, "Entries of the coarse CDF threshold table")
        ->capture_default_str();
    cmd->add_option("--sigma-t", o.diffusion.sigma_t_m, "Diffusion: translation sigma at iteration 0, metres")
        ->capture_default_str();
    cmd->add_option("--sigma-r", o.diffusion.sigma_r_rad, "Diffusion: rotation sigma at iteration 0, radians")
        ->capture_default_str();
    cmd->add_option("--sigma-t-min", o.diffusion.sigma_t_min_m, "Diffusion: smallest translation sigma, metres")
        ->capture_default_str();
    cmd->add_option("--sigma-r-min", o.diffusion.sigma_r_min_rad, "Diffusion: smallest rotation sigma, radians")
        ->capture_default_str();
    cmd->add_option("--anneal", o.diffusion.anneal, "Diffusion: sigma factor per iteration, (0, 1]")
        ->capture_default_str();
    cmd->add_option("--flip-rate", o.diffusion.flip_rate,
                    "Diffusion: probability that a resampled sample turns 180 degrees about a model axis, [0, 1]")
        ->capture_default_str();
  }
  if (groups & kAppearanceFlags) {
    cmd->add_option("--appearance", f->appearance,
                    "Colour: on (a colour term in the weight wherever the model and the frame have colour) or off "
                    "(depth only)")->capture_default_str();
    cmd->add_option("--colour-weight", o.appearance.weight,
                    "d in w = (1 - d) w_depth + d A, A the colour agreement of the depth inliers, [0, 1)")
        ->capture_default_str();
    cmd->add_option("--colour-space", f->colour_space,
                    "What the colour term compares: intensity-hue (intensity and normalised colour), chroma (normalised "
                    "colour, which shading does not change) or rgb")
        ->capture_default_str();
    cmd->add_flag("--resolve-twins,!--no-resolve-twins", o.appearance.resolve_twins,
                  "After the filter, score the best pose's depth twins on every pixel with colour and refine the best "
                  "(default on)");
    cmd->add_option("--twin-depth-margin", o.appearance.twin_depth_margin,
                    "Twin candidates within this of the best depth weight are told apart by colour alone; 0: by "
                    "the whole weight")
        ->capture_default_str();
    cmd->add_option("--twin-step", o.appearance.twin_step_deg,
                    "Twin candidates: turns about the model's most distinct axis in these steps, degrees")
        ->capture_default_str();
    cmd->add_option("--twin-refine", o.appearance.twin_refine_iterations,
                    "Iterations of the filter that refine the chosen twin")->capture_default_str();
    cmd->add_option("--colour-ramp", o.appearance.ramp_iterations,
                    "The colour term's weight grows over this many first iterations; 0: full from the start")
        ->capture_default_str();
    cmd->add_option("--colour-step", o.appearance.pixel_step,
                    "The colour test reads every n-th pixel of each box's grid in x and y, 1 to 4")->capture_default_str();
    cmd->add_option("--colour-smooth", o.appearance.smooth_radius,
                    "Each observed colour tested is the mean of the (2 r + 1)^2 pixels around it, r 0 to 3; 0: the "
                    "pixel alone")
        ->capture_default_str();
    cmd->add_flag("--colour-drop-clipped,!--no-colour-drop-clipped", o.appearance.drop_clipped,
                  "Leave out observed pixels with a clipped channel (at 255, or at a level many of the box's pixels "
                  "share)");
    cmd->add_option("--colour-trust-pixels", o.appearance.trust_pixels,
                    "Colour seen on n pixels counts n / (n + this) of its full say; 0: full say from --colour-min-pixels "
                    "on")
        ->capture_default_str();
    cmd->add_option("--colour-min-pixels", o.appearance.min_pixels,
                    "Fewer depth inliers of known colour than this: the neutral A = 0.5")->capture_default_str();
  }
  if (groups & kRefineFlags) {
    cmd->add_option("--refine", f->refine,
                    "Align the final pose to the observed depth (point-to-plane, robust), kept if its weight does not "
                    "drop: on or off")->capture_default_str();
    cmd->add_option("--refine-iterations", o.refine.max_iterations, "Alignment steps for the final pose")
        ->capture_default_str();
    cmd->add_option("--refine-twin-iterations", o.refine.twin_iterations,
                    "Alignment steps for each twin candidate")->capture_default_str();
    cmd->add_option("--refine-tukey", o.refine.tukey_m, "Robust (Tukey) loss scale of the alignment, metres")
        ->capture_default_str();
    cmd->add_option("--refine-max-distance", o.refine.max_distance_m,
                    "The alignment pairs no model and observed points farther apart than this, metres")
        ->capture_default_str();
    cmd->add_option("--refine-accept-eps", o.refine.accept_eps_m,
                    "Inlier threshold (m) of the weight that decides whether the aligned pose is kept; 0: --eps")
        ->capture_default_str();
  }
  if (groups & kEngineFlags) {
    cmd->add_option("--engine", f->engine,
                    "Raster core: scalar (float reference), float-simd (the reference a vector at a time, same "
                    "results), fixed (1/16-pixel fixed point) or simd (fixed point a vector at a time)")
        ->capture_default_str();
    cmd->add_option("--threads", o.engine.threads, "Raster cores (worker threads); 0 = all hardware threads")
        ->capture_default_str();
    cmd->add_option("--pixel-stride", o.engine.pixel_stride,
                    "Score every s-th pixel in x and y of each box; 1 with --max-grid-pixels 0 = every pixel")
        ->capture_default_str();
    cmd->add_option("--max-grid-pixels", o.engine.max_grid_pixels,
                    "Score a box with more grid pixels than this at a coarser stride; 0 = no budget")
        ->capture_default_str();
    cmd->add_option("--lod-px", o.engine.lod_error_px,
                    "Level of detail: the coarsest simplified mesh within this many image pixels of the full "
                    "mesh at the box's depth; 0 = full mesh")
        ->capture_default_str();
    f->lod_unbiased = cmd->add_flag("--lod-unbiased,!--no-lod-unbiased", o.engine.lod_unbiased,
                                    "LOD levels' vertices moved so that the full surface lies on each level on "
                                    "average (default on with LOD)");
    cmd->add_flag("--backface-culling,!--no-backface-culling", o.engine.backface_culling,
                  "Cull back-facing triangles (default on)");
    f->cluster_culling = cmd->add_flag("--cluster-culling,!--no-cluster-culling", o.engine.cluster_culling,
                                       "Drop whole triangle clusters outside the box or facing away before setup "
                                       "(default on with LOD on the fixed and simd engines)");
    f->batched_setup = cmd->add_flag("--batched-setup,!--no-batched-setup", o.engine.batched_setup,
                                     "Decide and set up triangles a SIMD vector at a time, same results (default "
                                     "on for the fixed and simd engines)");
    cmd->add_option("--simd-target", f->simd_target,
                    "Cap the SIMD dispatch at this Highway target (here: " + SimdTargets() +
                        "), e.g. AVX2 on an AVX-512 machine; same results; default: the best");
  }
}

Status EstimatorFlags::Finish() {
  EstimatorOptions& o = options;
  if (inlier == "1d") {
    o.weight.inlier = InlierMode::k1D;
  } else if (inlier == "3d") {
    o.weight.inlier = InlierMode::k3D;
  } else {
    return InvalidArgument("--inlier must be 1d or 3d, got '" + inlier + "'");
  }
  if (appearance == "on" || appearance == "off") {
    o.appearance.enabled = appearance == "on";
  } else {
    return InvalidArgument("--appearance must be on or off, got '" + appearance + "'");
  }
  if (refine == "on" || refine == "off") {
    o.refine.enabled = refine == "on";
  } else {
    return InvalidArgument("--refine must be on or off, got '" + refine + "'");
  }
  if (!AppearanceOptions::ParseSpace(colour_space, &o.appearance.space))
    return InvalidArgument(std::string("--colour-space must be ") + AppearanceOptions::kSpaceChoices + ", got '" +
                           colour_space + "'");
  if (!weights.empty()) {
    if (weights.size() != 3) return InvalidArgument("--weights takes three numbers a b c");
    o.weight.a = weights[0], o.weight.b = weights[1], o.weight.c = weights[2];
  }
  if (!ParseRasterBackend(engine, &o.engine.backend))
    return InvalidArgument(std::string("--engine must be ") + kRasterBackendChoices + ", got '" + engine + "'");
  EngineOptions usable = o.engine;
  usable.DropUnusableFeatures();
  const auto given = [](const CLI::Option* opt) { return opt != nullptr && opt->count() > 0; };
  if (!given(lod_unbiased)) o.engine.lod_unbiased = usable.lod_unbiased;
  if (!given(cluster_culling)) o.engine.cluster_culling = usable.cluster_culling;
  if (!given(batched_setup)) o.engine.batched_setup = usable.batched_setup;
  if (!simd_target.empty() && !render::LimitSimdTargets(simd_target))
    return InvalidArgument("--simd-target must be one of: " + SimdTargets() + "; got '" + simd_target + "'");
  std::string error;
  if (!o.IsValid(&error)) return InvalidArgument("invalid options: " + error);
  return Status::Ok();
}

namespace {

// Parses `args` with the flags `app` holds, then finishes the estimator's `flags`.
Status ParseArgs(CLI::App& app, EstimatorFlags& flags, const std::vector<std::string>& args) {
  std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes them last first
  try {
    app.parse(reversed);
  } catch (const CLI::ParseError& e) {
    return InvalidArgument(e.what());
  }
  return flags.Finish();
}

}  // namespace

StatusOr<EstimatorOptions> ParseEstimatorOptions(const std::vector<std::string>& args) {
  CLI::App app{"mcpose estimator options"};
  EstimatorFlags flags;
  AddEstimatorFlags(&app, kAllEstimatorFlags, &flags);
  MCPOSE_RETURN_IF_ERROR(ParseArgs(app, flags, args));
  return flags.options;
}

void AddTrackerFlags(CLI::App* cmd, TrackerOptions* t) {
  cmd->add_option("--track-samples", t->samples, "Samples of a tracked frame")->capture_default_str();
  cmd->add_option("--track-iterations", t->iterations, "Filter iterations of a tracked frame")->capture_default_str();
  cmd->add_option("--stop-weight", t->stop_weight, "A tracked frame stops when its mean weight exceeds this")->capture_default_str();
  cmd->add_option("--motion-sigma-t", t->motion_sigma_t_m, "Motion model: translation noise per frame, metres")->capture_default_str();
  cmd->add_option("--motion-sigma-r", t->motion_sigma_r_rad, "Motion model: rotation noise per frame, radians")->capture_default_str();
  cmd->add_option("--box-margin", t->box_margin, "A tracked frame's box: the last silhouette grown by this fraction a side")
      ->capture_default_str();
  cmd->add_option("--track-refine-iterations", t->refine_iterations,
                  "Refinement steps in a tracked frame (0: none)")->capture_default_str();
  cmd->add_option("--lost-fit", t->lost_fit,
                  "The track is lost where the share of the answer's visible silhouette that the depth confirms is "
                  "below this")
      ->capture_default_str();
  cmd->add_option("--lost-visible", t->lost_visible,
                  "The track is lost where the share of the answer's silhouette not hidden behind nearer surfaces is "
                  "below this")
      ->capture_default_str();
}

StatusOr<TrackerOptions> ParseTrackerOptions(const std::vector<std::string>& args) {
  CLI::App app{"mcpose tracker options"};
  EstimatorFlags flags;
  TrackerOptions options;
  AddTrackerFlags(&app, &options);
  AddEstimatorFlags(&app, kAllEstimatorFlags & ~kInstanceFlags, &flags);
  MCPOSE_RETURN_IF_ERROR(ParseArgs(app, flags, args));
  options.estimator = flags.options;
  std::string error;
  if (!options.IsValid(&error)) return InvalidArgument("invalid tracker options: " + error);
  return options;
}

bool IsEstimatorSwitch(const std::string& name) {
  CLI::App app;
  EstimatorFlags flags;
  AddEstimatorFlags(&app, kAllEstimatorFlags, &flags);
  const CLI::Option* opt = app.get_option_no_throw("--" + name);
  return opt != nullptr && opt->get_expected_min() == 0;
}

void RemoveOutput(const std::string& path) {
  if (path.empty()) return;
  std::error_code ec;
  std::filesystem::remove(path, ec);
}

Status CheckWritable(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path p(path);
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return NotFound(path + ": folder " + dir.string() + " does not exist");
  if (fs::is_directory(p, ec)) return InvalidArgument(path + ": is a folder, expected a file path");
  // The probe is created exclusively under a fresh name: it follows no link and touches no file.
  StatusOr<io::TempFile> probe = io::CreateTempFileBeside(path);
  if (!probe.ok()) return InvalidArgument(path + ": cannot create files in " + dir.string());
  ::close(probe->fd);
  fs::remove(probe->path, ec);
  return Status::Ok();
}

namespace {

// Two paths name the same file: the same after resolving links and "..", or (where both exist)
// the same inode.
bool SameFile(const std::string& a, const std::string& b) {
  namespace fs = std::filesystem;
  std::error_code ec1, ec2;
  const fs::path ca = fs::weakly_canonical(fs::absolute(a), ec1), cb = fs::weakly_canonical(fs::absolute(b), ec2);
  if (!ec1 && !ec2 && ca == cb) return true;
  std::error_code ec;
  return fs::exists(a, ec) && fs::exists(b, ec) && fs::equivalent(a, b, ec) && !ec;
}

}  // namespace

const CLI::Validator& SeedCheck() {
  static const CLI::Validator check(
      [](std::string& text) -> std::string {
        uint64_t value = 0;
        const char* end = text.data() + text.size();
        const auto [ptr, ec] = std::from_chars(text.data(), end, value);
        if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos || ec != std::errc() ||
            ptr != end)
          return "a seed is a whole number from 0 to 18446744073709551615, got '" + text + "'";
        return {};
      },
      "SEED", "seed");
  return check;
}

Status CheckOutputsDistinct(std::initializer_list<PathArg> inputs, std::initializer_list<PathArg> outputs) {
  for (auto out = outputs.begin(); out != outputs.end(); ++out) {
    if (out->path.empty()) continue;
    for (const PathArg& in : inputs)
      if (!in.path.empty() && SameFile(out->path, in.path))
        return InvalidArgument(out->path + ": " + out->flag + " names the same file as " + in.flag +
                               ", an input of this run; it would be overwritten");
    for (auto other = outputs.begin(); other != out; ++other)
      if (!other->path.empty() && SameFile(out->path, other->path))
        return InvalidArgument(out->path + ": " + out->flag + " and " + other->flag + " name the same file");
  }
  return Status::Ok();
}

Status CheckOutputsOutsideDataset(const Dataset& dataset, std::initializer_list<PathArg> outputs) {
  namespace fs = std::filesystem;
  const auto canonical = [](const std::string& path) {
    std::error_code ec;
    const fs::path p = fs::weakly_canonical(fs::absolute(path), ec);
    return ec ? fs::absolute(path).lexically_normal() : p;
  };
  // Whether `inner` is `outer` or lies below it (both canonical).
  const auto within = [](const fs::path& inner, const fs::path& outer) {
    const fs::path rel = inner.lexically_relative(outer);
    return !rel.empty() && *rel.begin() != "..";
  };
  for (const PathArg& out : outputs) {
    if (out.path.empty()) continue;
    const fs::path o = canonical(out.path);
    std::error_code ec;
    for (const std::string& folder : {dataset.root(), dataset.models_dir()}) {
      const fs::path f = canonical(folder);
      if (within(f, o))
        return InvalidArgument(out.path + ": " + out.flag + " names a folder holding the dataset " + folder +
                               ", which this run reads");
      if (within(o, f) && fs::exists(fs::symlink_status(out.path, ec)))
        return InvalidArgument(out.path + ": " + out.flag + " names what the dataset folder " + folder +
                               " holds, which this run may read; it would be overwritten (write elsewhere)");
    }
  }
  return Status::Ok();
}

Status KeepScoresAtLeast(double min_score, const std::string& source, std::vector<Detection>* detections) {
  if (!(min_score >= 0 && min_score <= 1)) return InvalidArgument("--min-score must lie in [0, 1]");
  if (min_score == 0) return Status::Ok();
  std::erase_if(*detections, [&](const Detection& d) { return d.score < min_score; });
  if (detections->empty()) return InvalidArgument(source + ": no detection scores at least --min-score " + limits::Num(min_score));
  return Status::Ok();
}

std::string ActiveSimdTarget() { return render::DispatchedSimdTarget(); }
std::string SimdTargets() { return render::SimdTargetsAvailable(); }

}  // namespace mcpose::cli

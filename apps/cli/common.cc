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
  for (const OptionField& field : EstimatorOptionFields()) {
    if (!(groups & field.group)) continue;
    if (field.flag == nullptr) {  // weight.a, b, c: one flag for the three, with the first
      if (std::string(field.key) != "weight.a") continue;
      char help[128];
      std::snprintf(help, sizeof help,
                    "Weight coefficients a b c (sum 1): w = a N/N_b + b N/N_r + c score (default %.2f %.2f %.2f)",
                    o.weight.a, o.weight.b, o.weight.c);
      cmd->add_option("--weights", f->weights, help)->expected(3);
      continue;
    }
    const std::string flag = field.flag;
    switch (field.type) {
      case OptionField::Type::kInt:
        cmd->add_option(flag, field.Ref<int>(o), field.doc)->capture_default_str();
        break;
      case OptionField::Type::kSeed:
        cmd->add_option(flag, field.Ref<uint64_t>(o), field.doc)->check(SeedCheck())->capture_default_str();
        break;
      case OptionField::Type::kDouble:
        cmd->add_option(flag, field.Ref<double>(o), field.doc)->capture_default_str();
        break;
      case OptionField::Type::kBool:
        if (field.style == OptionField::Switch::kOnOff) {
          std::string& text = f->text[field.key] = field.Text(o);
          cmd->add_option(flag, text, field.doc)->capture_default_str();
        } else {
          const CLI::Option* opt = cmd->add_flag(flag + ",!--no-" + flag.substr(2), field.Ref<bool>(o),
                                                 std::string(field.doc) + " (default " + field.Text(o) + ")");
          if (std::string(field.key).starts_with("engine.")) f->given[field.key] = opt;
        }
        break;
      case OptionField::Type::kEnum: {
        std::string& text = f->text[field.key] = field.Text(o);
        cmd->add_option(flag, text, field.doc)->capture_default_str();
        break;
      }
    }
  }
  if (groups & kEngineFlags)
    cmd->add_option("--simd-target", f->simd_target,
                    "Cap the SIMD dispatch at this Highway target (here: " + SimdTargets() +
                        "), e.g. AVX2 on an AVX-512 machine; same results; default: the best");
}

Status EstimatorFlags::Finish() {
  EstimatorOptions& o = options;
  for (const auto& [key, value] : text) {
    const OptionField& field = *FindOptionField(key);
    if (!field.Parse(value, &o))
      return InvalidArgument(std::string(field.flag) + " must be " +
                             (field.type == OptionField::Type::kBool ? std::string("on or off")
                                                                     : ChoicesText(field.names)) +
                             ", got '" + value + "'");
  }
  if (!weights.empty()) {
    if (weights.size() != 3) return InvalidArgument("--weights takes three numbers a b c");
    o.weight.a = weights[0], o.weight.b = weights[1], o.weight.c = weights[2];
  }
  EstimatorOptions usable = o;
  usable.engine.DropUnusableFeatures();
  for (const auto& [key, opt] : given)
    if (opt->count() == 0) {
      const OptionField& field = *FindOptionField(key);
      field.Ref<bool>(o) = field.Get<bool>(usable);
    }
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

StatusOr<EstimatorOptions> ParseEstimatorOptions(const std::vector<std::string>& args, const EstimatorOptions& base) {
  CLI::App app{"mcpose estimator options"};
  EstimatorFlags flags;
  flags.options = base;
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

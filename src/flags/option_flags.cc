#include "mcpose/option_flags.h"

#include <charconv>
#include <cstdint>
#include <cstdio>
#include <stdexcept>

#include "engine/context.h"

namespace mcpose {

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
  std::string error;
  if (!o.IsValid(&error)) return InvalidArgument("invalid options: " + error);
  MCPOSE_RETURN_IF_ERROR(engine::CheckSimdTarget(o.engine));
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
  AddEstimatorFlags(&app, kAllOptions, &flags);
  MCPOSE_RETURN_IF_ERROR(ParseArgs(app, flags, args));
  return flags.options;
}

void AddTrackerFlags(CLI::App* cmd, TrackerOptions* t) {
  for (const TrackerOptionField& field : TrackerOptionFields()) {
    switch (field.type) {
      case TrackerOptionField::Type::kInt:
        cmd->add_option(field.flag, field.Ref<int>(*t), field.doc)->capture_default_str();
        break;
      case TrackerOptionField::Type::kDouble:
        cmd->add_option(field.flag, field.Ref<double>(*t), field.doc)->capture_default_str();
        break;
      case TrackerOptionField::Type::kSeed:
        cmd->add_option(field.flag, field.Ref<uint64_t>(*t), field.doc)->check(SeedCheck())->capture_default_str();
        break;
      case TrackerOptionField::Type::kBool:
      case TrackerOptionField::Type::kEnum:  // no tracker option is one yet: bind it as the estimator's are
        throw std::logic_error(std::string(field.flag) + ": a tracker switch or enum needs its flag binding");
    }
  }
}

StatusOr<TrackerOptions> ParseTrackerOptions(const std::vector<std::string>& args) {
  CLI::App app{"mcpose tracker options"};
  EstimatorFlags flags;
  TrackerOptions options;
  AddTrackerFlags(&app, &options);
  AddEstimatorFlags(&app, kAllOptions & ~kInstanceOptions, &flags);
  MCPOSE_RETURN_IF_ERROR(ParseArgs(app, flags, args));
  options.estimator = flags.options;
  std::string error;
  if (!options.IsValid(&error)) return InvalidArgument("invalid tracker options: " + error);
  return options;
}

bool IsEstimatorSwitch(const std::string& name) {
  CLI::App app;
  EstimatorFlags flags;
  AddEstimatorFlags(&app, kAllOptions, &flags);
  const CLI::Option* opt = app.get_option_no_throw("--" + name);
  return opt != nullptr && opt->get_expected_min() == 0;
}

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

}  // namespace mcpose

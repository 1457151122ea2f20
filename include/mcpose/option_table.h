// Every field of EstimatorOptions, declared once (src/core/option_table.cc): its JSON key, its
// command-line flag, type, bounds, unit and one-line doc. From this table come the flags of
// `mcpose estimate` and `track` (and so the Python package's keyword options), the options'
// JSON (a run's fingerprint, `--out-json`), the bounds EstimatorOptions::IsValid checks, and
// the options table of docs/options.md (checked by a test). Adding an option is a field in
// include/mcpose/options.h, one line here, and its use.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "mcpose/options.h"

namespace mcpose {

struct OptionField {
  enum class Type { kInt, kSeed, kDouble, kBool, kEnum };
  // How a kBool is set on the command line: --flag / --no-flag, or --flag on|off.
  enum class Switch { kPair, kOnOff };

  const char* key;   // the JSON path: "refine.tukey_m"
  const char* flag;  // "--refine-tukey"; nullptr: a flag of several fields sets it (--weights)
  Type type;
  void* (*at)(EstimatorOptions& options);  // the field in `options` (of `type`)
  // Bounds of a kInt or kDouble (a kDouble must also be finite); min_open / max_open: the
  // bound itself is out.
  double min = 0, max = 0;
  bool min_open = false, max_open = false;
  const char* unit = "";  // "m", "rad", "deg", "px", "pixels" or "" (a count or a share)
  const char* doc = "";   // one line, as in `--help`
  unsigned group = 0;     // the flag group (FlagGroup in apps/cli/common.h)
  Switch style = Switch::kPair;
  std::span<const char* const> names;  // kEnum: the names of its values, by value

  // The field in `options` as T, its C++ type: int (kInt, and kEnum's value), uint64_t (kSeed),
  // double or bool.
  template <class T>
  T& Ref(EstimatorOptions& options) const {
    return *static_cast<T*>(at(options));
  }
  template <class T>
  const T& Get(const EstimatorOptions& options) const {
    return Ref<T>(const_cast<EstimatorOptions&>(options));  // read only
  }

  // The field's value as the command line and JSON spell it: "620", "0.01", "on", "simd".
  std::string Text(const EstimatorOptions& options) const;
  // Sets a kBool ("on", "off") or kEnum field from that spelling; false (and no change) for a
  // bad one or another type (numbers are parsed by CLI11 and nlohmann::json).
  bool Parse(const std::string& text, EstimatorOptions* options) const;
  // "" if the value of `options` lies within the bounds, else "<key> must lie in [a, b], got v".
  std::string CheckBounds(const EstimatorOptions& options) const;
  // The bounds as the docs print them: "[1, 1000000]", "> 0", "finite", "on, off", "1d or 3d".
  std::string BoundsText() const;
};

// The flag groups of the table's fields: which commands take which flags.
enum OptionGroup : unsigned {
  kSamplingOptions = 1u << 0,    // --samples --seed
  kStoppingOptions = 1u << 1,    // --iterations --tau
  kWeightOptions = 1u << 2,      // --inlier --eps --weights --[no-]occlusion-aware --box-fit
  kSearchOptions = 1u << 3,      // initialization, resampling and diffusion
  kEngineOptions = 1u << 4,      // --engine, its features, --threads
  kAppearanceOptions = 1u << 5,  // --appearance and the colour term
  kRefineOptions = 1u << 6,      // --refine ...
  kInstanceOptions = 1u << 7,    // --max-instances (estimation jobs, not tracking)
  kAllOptions = 0xff,
};

// The table, in the order of `--help`.
std::span<const OptionField> EstimatorOptionFields();
// The field of JSON path `key`; nullptr if none.
const OptionField* FindOptionField(const std::string& key);

// The names of each enum's values, by value: what the command line and JSON accept.
std::span<const char* const> InlierModeNames();
std::span<const char* const> RasterBackendNames();
std::span<const char* const> ColourSpaceNames();
// The options table of docs/options.md: one row per field (flag, JSON key, default, bounds,
// unit, doc), in the table's order.
std::string OptionTableMarkdown();

// "a, b or c" of `names`, for messages.
std::string ChoicesText(std::span<const char* const> names);

}  // namespace mcpose

// Every field of EstimatorOptions and of TrackerOptions, declared once (src/core/option_table.cc):
// its JSON key, its command-line flag, type, bounds, unit and one-line doc. From these tables
// come the flags of `mcpose estimate` and `track` (mcpose/option_flags.h, and so the Python
// package's keyword options), the options' JSON (a run's fingerprint, `--out-json`), the bounds
// EstimatorOptions::IsValid and TrackerOptions::IsValid check, and the tables of
// docs/options.md (checked by a test). Adding an option is a field in include/mcpose/options.h
// (or tracker.h), one line in the table, and its use.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "mcpose/options.h"

namespace mcpose {

struct TrackerOptions;  // mcpose/tracker.h

// An option's type, and how a bool is set on the command line: --flag / --no-flag (kPair), or
// --flag on|off (kOnOff).
enum class OptionType { kInt, kSeed, kDouble, kBool, kEnum };
enum class OptionSwitch { kPair, kOnOff };

// A field of an options struct `Options` (EstimatorOptions or TrackerOptions).
template <class Options>
struct BasicOptionField {
  using Type = OptionType;
  using Switch = OptionSwitch;

  const char* key;   // the JSON path: "refine.tukey_m"
  const char* flag;  // "--refine-tukey"; nullptr: a flag of several fields sets it (--weights)
  Type type;
  void* (*at)(Options& options);  // the field in `options` (of `type`)
  // Bounds of a kInt or kDouble (a kDouble must also be finite); min_open / max_open: the
  // bound itself is out.
  double min = 0, max = 0;
  bool min_open = false, max_open = false;
  const char* unit = "";  // "m", "rad", "deg", "px", "pixels" or "" (a count or a share)
  const char* doc = "";   // one line, as in `--help`
  unsigned group = 0;     // the flag group (OptionGroup below)
  Switch style = Switch::kPair;
  std::span<const char* const> names;  // kEnum: the names of its values, by value

  // The field in `options` as T, its C++ type: int (kInt, and kEnum's value), uint64_t (kSeed),
  // double or bool.
  template <class T>
  T& Ref(Options& options) const {
    return *static_cast<T*>(at(options));
  }
  template <class T>
  const T& Get(const Options& options) const {
    return Ref<T>(const_cast<Options&>(options));  // read only
  }

  // The field's value as the command line and JSON spell it: "620", "0.01", "on", "simd".
  std::string Text(const Options& options) const;
  // Sets a kBool ("on", "off") or kEnum field from that spelling; false (and no change) for a
  // bad one or another type (numbers are parsed by CLI11 and nlohmann::json).
  bool Parse(const std::string& text, Options* options) const;
  // "" if the value of `options` lies within the bounds, else "<key> must lie in [a, b], got v".
  std::string CheckBounds(const Options& options) const;
  // The bounds as the docs print them: "[1, 1000000]", "> 0", "finite", "on, off", "1d or 3d".
  std::string BoundsText() const;
};

using OptionField = BasicOptionField<EstimatorOptions>;
using TrackerOptionField = BasicOptionField<TrackerOptions>;

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
  kTrackerOptions = 1u << 8,     // the tracker's own: --track-samples ... (TrackerOptionFields)
  kAllOptions = 0xff,            // every estimator option
};

// The table, in the order of `--help`.
std::span<const OptionField> EstimatorOptionFields();
// The field of JSON path `key`; nullptr if none.
const OptionField* FindOptionField(const std::string& key);
// The tracker's own fields (TrackerOptions but its `estimator`), likewise.
std::span<const TrackerOptionField> TrackerOptionFields();
const TrackerOptionField* FindTrackerOptionField(const std::string& key);

// The names of each enum's values, by value: what the command line and JSON accept.
std::span<const char* const> InlierModeNames();
std::span<const char* const> RasterBackendNames();
std::span<const char* const> ColourSpaceNames();
// "best", then the SIMD targets this build compiled, best first (SimdTarget).
std::span<const char* const> SimdTargetNames();
// The options table of docs/options.md: one row per field (flag, JSON key, default, bounds,
// unit, doc), in the table's order.
std::string OptionTableMarkdown();
// The same of the tracker's own fields.
std::string TrackerOptionTableMarkdown();

// "a, b or c" of `names`, for messages.
std::string ChoicesText(std::span<const char* const> names);

}  // namespace mcpose

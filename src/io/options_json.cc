#include "mcpose/options_json.h"

#include <cstdint>

#include "mcpose/option_table.h"

namespace mcpose::io {

nlohmann::json::json_pointer OptionPointer(const char* key) {
  std::string path = std::string("/") + key;
  for (char& c : path)
    if (c == '.') c = '/';
  return nlohmann::json::json_pointer(path);
}

namespace {

// The value of field `f` of `o` as JSON: a number, true/false, or an enum's name.
template <class Options>
nlohmann::json FieldJson(const BasicOptionField<Options>& f, const Options& o) {
  using Type = typename BasicOptionField<Options>::Type;
  switch (f.type) {
    case Type::kInt: return f.template Get<int>(o);
    case Type::kSeed: return f.template Get<uint64_t>(o);
    case Type::kDouble: return f.template Get<double>(o);
    case Type::kBool: return f.template Get<bool>(o);
    case Type::kEnum: return f.Text(o);
  }
  return nullptr;
}

}  // namespace

nlohmann::json OptionsToJson(const EstimatorOptions& o) {
  nlohmann::json j = nlohmann::json::object();
  for (const OptionField& f : EstimatorOptionFields()) j[OptionPointer(f.key)] = FieldJson(f, o);
  return j;
}

StatusOr<EstimatorOptions> OptionsFromJson(const nlohmann::json& json) {
  if (!json.is_object()) return InvalidArgument("options: expected a JSON object");
  EstimatorOptions o;
  const nlohmann::json flat = json.flatten();
  for (const auto& item : flat.items()) {
    std::string key = item.key().substr(1);  // "/refine/tukey_m" -> "refine.tukey_m"
    for (char& c : key)
      if (c == '/') c = '.';
    const OptionField* f = FindOptionField(key);
    if (f == nullptr) return InvalidArgument("options: unknown key '" + key + "'");
    const nlohmann::json& v = item.value();
    const auto wrong = [&](const std::string& want) {
      return InvalidArgument("options: " + key + " must be " + want + ", got " + v.dump());
    };
    switch (f->type) {
      case OptionField::Type::kInt:
        if (!v.is_number_integer() || v.get<int64_t>() < INT32_MIN || v.get<int64_t>() > INT32_MAX)
          return wrong("a whole number");
        f->Ref<int>(o) = v.get<int>();
        break;
      case OptionField::Type::kSeed:
        if (!v.is_number_unsigned()) return wrong("a whole number >= 0");
        f->Ref<uint64_t>(o) = v.get<uint64_t>();
        break;
      case OptionField::Type::kDouble:
        if (!v.is_number()) return wrong("a number");
        f->Ref<double>(o) = v.get<double>();
        break;
      case OptionField::Type::kBool:
        if (!v.is_boolean()) return wrong("true or false");
        f->Ref<bool>(o) = v.get<bool>();
        break;
      case OptionField::Type::kEnum:
        if (!v.is_string() || !f->Parse(v.get<std::string>(), &o)) return wrong(ChoicesText(f->names));
        break;
    }
  }
  std::string error;
  if (!o.IsValid(&error)) return InvalidArgument("options: " + error);
  return o;
}

nlohmann::json CountersToJson(const EngineCounters& c) {
  nlohmann::json j = nlohmann::json::object();
#define MCPOSE_COUNTER_JSON(name, doc) j[#name] = c.name;
  MCPOSE_ENGINE_COUNTERS(MCPOSE_COUNTER_JSON)
#undef MCPOSE_COUNTER_JSON
  return j;
}

nlohmann::json TrackerOptionsToJson(const TrackerOptions& t) {
  nlohmann::json j = nlohmann::json::object();
  for (const TrackerOptionField& f : TrackerOptionFields()) j[f.key] = FieldJson(f, t);
  j["estimator"] = OptionsToJson(t.estimator);
  return j;
}

}  // namespace mcpose::io

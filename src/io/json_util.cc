#include "mcpose/json_util.h"

#include <cmath>
#include <exception>
#include <limits>
#include <set>
#include <stdexcept>
#include <vector>

#include "mcpose/limits.h"
#include "mcpose/io_util.h"

namespace mcpose::io {

namespace {

// Thrown by the parser callback on a key seen twice in one object (nlohmann/json keeps the last).
struct DuplicateKey : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Thrown by the parser callback past limits::kMaxJsonDepth levels of nesting.
struct TooDeep : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace

StatusOr<nlohmann::json> ReadJsonFile(const std::string& path) {
  MCPOSE_ASSIGN_OR_RETURN(std::string text, ReadFileToString(path));
  // The keys of each open object, innermost last.
  std::vector<std::set<std::string>> open_objects;
  const auto check_keys = [&](int depth, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
    using Event = nlohmann::json::parse_event_t;
    if (depth > limits::kMaxJsonDepth) throw TooDeep("");
    if (event == Event::object_start) {
      open_objects.emplace_back();
    } else if (event == Event::object_end) {
      if (!open_objects.empty()) open_objects.pop_back();
    } else if (event == Event::key && !open_objects.empty()) {
      const std::string& key = parsed.get_ref<const std::string&>();
      if (!open_objects.back().insert(key).second) throw DuplicateKey(key);
    }
    return true;
  };
  try {
    return nlohmann::json::parse(text, check_keys);
  } catch (const TooDeep&) {
    return DataLoss(path + ": JSON nested more than " + std::to_string(limits::kMaxJsonDepth) + " levels deep");
  } catch (const DuplicateKey& e) {
    return DataLoss(path + ": duplicate key '" + e.what() + "' in one object");
  } catch (const std::exception& e) {
    std::string message = path + ": malformed JSON (" + e.what() + ")";
    // Python's json module writes NaN / Infinity for non-finite floats; JSON has no such values.
    if (text.find("NaN") != std::string::npos || text.find("Infinity") != std::string::npos) {
      message += "; non-finite numbers such as NaN or Infinity are not valid JSON";
    }
    return DataLoss(message);
  }
}

bool JsonToDouble(const nlohmann::json& value, double* out) {
  if (!value.is_number()) return false;
  const double v = value.get<double>();
  if (!std::isfinite(v)) return false;
  *out = v;
  return true;
}

bool JsonToInt(const nlohmann::json& value, int* out) {
  if (value.is_number_integer()) {  // signed or unsigned
    if (value.is_number_unsigned()) {
      const auto u = value.get<uint64_t>();
      if (u > static_cast<uint64_t>(std::numeric_limits<int>::max())) return false;
      *out = static_cast<int>(u);
      return true;
    }
    const auto i = value.get<int64_t>();
    if (i < std::numeric_limits<int>::min() || i > std::numeric_limits<int>::max()) return false;
    *out = static_cast<int>(i);
    return true;
  }
  if (value.is_number_float()) {  // 49.0 written by a float-happy writer
    const double v = value.get<double>();
    if (!std::isfinite(v) || v != std::floor(v) || std::fabs(v) > 2e9) return false;
    *out = static_cast<int>(v);
    return true;
  }
  return false;
}

bool JsonToDoubles(const nlohmann::json& value, size_t n, double* out) {
  if (!value.is_array() || value.size() != n) return false;
  for (size_t i = 0; i < n; ++i) {
    if (!JsonToDouble(value[i], &out[i])) return false;
  }
  return true;
}

bool IsIdKey(const std::string& s) {
  return !s.empty() && s.size() <= 9 && s.find_first_not_of("0123456789") == std::string::npos &&
         (s.size() == 1 || s[0] != '0');
}

}  // namespace mcpose::io

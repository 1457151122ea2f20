// JSON file reading for the BOP and detection readers: nlohmann/json exceptions stop here.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "mcpose/status.h"

namespace mcpose::io {

// The parsed contents of `path`. NotFound if missing; DataLoss with the parser's message
// (line and column) if the text is not valid JSON or an object has the same key twice.
StatusOr<nlohmann::json> ReadJsonFile(const std::string& path);

// `value` as a finite double; false if it is not a number (booleans are not numbers).
bool JsonToDouble(const nlohmann::json& value, double* out);
// `value` as an int; false unless it is a number with an integral value in int range.
bool JsonToInt(const nlohmann::json& value, int* out);
// `value` as exactly `n` finite numbers; false otherwise.
bool JsonToDoubles(const nlohmann::json& value, size_t n, double* out);

// An id as a JSON key: 1-9 decimal digits without leading zeros ("6", not "06"), so that one id
// has one key.
bool IsIdKey(const std::string& s);

}  // namespace mcpose::io

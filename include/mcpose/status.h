// Status and StatusOr: the error channel for bad input (files, options, data).
// Broken invariants are not reported through Status; they hit MCPOSE_CHECK (src/core/check.h).
#pragma once

#include <optional>
#include <string>
#include <utility>

namespace mcpose {

enum class StatusCode {
  kOk = 0,
  kInvalidArgument,  // bad option, bad value inside a file, unknown class, ...
  kNotFound,         // a file or an entry that should exist does not
  kDataLoss,         // a file exists but cannot be decoded (truncated, wrong format)
  kInternal,         // an external library failed in an unexpected way
};

class [[nodiscard]] Status {
 public:
  Status() = default;
  Status(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}
  static Status Ok() { return Status(); }

  bool ok() const { return code_ == StatusCode::kOk; }
  StatusCode code() const { return code_; }
  const std::string& message() const { return message_; }
  // "invalid argument: <message>" style text for logs and the CLI.
  std::string ToString() const;

 private:
  StatusCode code_ = StatusCode::kOk;
  std::string message_;
};

inline Status InvalidArgument(std::string m) { return Status(StatusCode::kInvalidArgument, std::move(m)); }
inline Status NotFound(std::string m) { return Status(StatusCode::kNotFound, std::move(m)); }
inline Status DataLoss(std::string m) { return Status(StatusCode::kDataLoss, std::move(m)); }
inline Status Internal(std::string m) { return Status(StatusCode::kInternal, std::move(m)); }

// A value or the Status that explains why there is none.
template <typename T>
class [[nodiscard]] StatusOr {
 public:
  StatusOr(T value) : value_(std::move(value)) {}  // NOLINT: implicit by design
  StatusOr(Status status) : status_(std::move(status)) {}  // NOLINT: implicit by design

  bool ok() const { return status_.ok(); }
  const Status& status() const { return status_; }
  T& value() & { return *value_; }
  const T& value() const& { return *value_; }
  T&& value() && { return std::move(*value_); }
  T& operator*() & { return *value_; }
  const T& operator*() const& { return *value_; }
  T* operator->() { return &*value_; }
  const T* operator->() const { return &*value_; }

 private:
  Status status_;
  std::optional<T> value_;
};

}  // namespace mcpose

#define MCPOSE_STATUS_CONCAT_INNER(a, b) a##b
#define MCPOSE_STATUS_CONCAT(a, b) MCPOSE_STATUS_CONCAT_INNER(a, b)

// Returns the Status of `expr` from the enclosing function if it is not ok.
#define MCPOSE_RETURN_IF_ERROR(expr)              \
  do {                                            \
    ::mcpose::Status mcpose_status_ = (expr);     \
    if (!mcpose_status_.ok()) return mcpose_status_; \
  } while (0)

// `lhs = value of expr`, or returns its Status from the enclosing function.
#define MCPOSE_ASSIGN_OR_RETURN(lhs, expr) \
  MCPOSE_ASSIGN_OR_RETURN_IMPL(MCPOSE_STATUS_CONCAT(mcpose_statusor_, __LINE__), lhs, expr)
#define MCPOSE_ASSIGN_OR_RETURN_IMPL(tmp, lhs, expr) \
  auto tmp = (expr);                                 \
  if (!tmp.ok()) return tmp.status();                \
  lhs = std::move(tmp).value()

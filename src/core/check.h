// Invariant checks. A failed check is a bug in mcpose, not bad input: it prints the
// expression, both operands and the location, then aborts. Bad input goes through Status.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

namespace mcpose::internal {

[[noreturn]] inline void CheckFailed(const char* file, int line, const std::string& what) {
  std::fprintf(stderr, "mcpose: internal check failed at %s:%d: %s\n", file, line, what.c_str());
  std::abort();
}

template <typename A, typename B>
std::string CheckOpMessage(const char* expr, const A& a, const B& b) {
  std::ostringstream os;
  os << expr << " (" << a << " vs. " << b << ")";
  return os.str();
}

}  // namespace mcpose::internal

#define MCPOSE_CHECK(cond)                                                          \
  do {                                                                              \
    if (!(cond)) ::mcpose::internal::CheckFailed(__FILE__, __LINE__, #cond);        \
  } while (0)

#define MCPOSE_CHECK_OP(a, op, b)                                                   \
  do {                                                                              \
    const auto& mcpose_a_ = (a);                                                    \
    const auto& mcpose_b_ = (b);                                                    \
    if (!(mcpose_a_ op mcpose_b_))                                                  \
      ::mcpose::internal::CheckFailed(                                              \
          __FILE__, __LINE__,                                                       \
          ::mcpose::internal::CheckOpMessage(#a " " #op " " #b, mcpose_a_, mcpose_b_)); \
  } while (0)

#define MCPOSE_CHECK_EQ(a, b) MCPOSE_CHECK_OP(a, ==, b)
#define MCPOSE_CHECK_NE(a, b) MCPOSE_CHECK_OP(a, !=, b)
#define MCPOSE_CHECK_LT(a, b) MCPOSE_CHECK_OP(a, <, b)
#define MCPOSE_CHECK_LE(a, b) MCPOSE_CHECK_OP(a, <=, b)
#define MCPOSE_CHECK_GT(a, b) MCPOSE_CHECK_OP(a, >, b)
#define MCPOSE_CHECK_GE(a, b) MCPOSE_CHECK_OP(a, >=, b)

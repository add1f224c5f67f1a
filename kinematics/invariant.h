// The invariant tier: internal contracts (index ranges, buffer sizes, states a caller must not
// reach) checked always, also in Release builds. A failed invariant is a bug in this program, not
// bad input: it prints the condition, the message and where, and aborts. User input (files,
// options, actions) is checked at load time and reported with exceptions naming the bad value.
#pragma once

#include <cstdio>
#include <cstdlib>

namespace tavis::kinematics::internal {

[[noreturn]] inline void InvariantFailed(const char* condition, const char* message, const char* file, int line) {
  std::fprintf(stderr, "tavis: internal invariant violated at %s:%d: %s (%s)\n", file, line, message, condition);
  std::abort();
}

}  // namespace tavis::kinematics::internal

// TAVIS_INVARIANT(index < size, "object index in range"): cheap enough for the hot loop (one
// predictable branch).
#define TAVIS_INVARIANT(condition, message)                                                    \
  do {                                                                                         \
    if (__builtin_expect(!(condition), 0)) {                                                   \
      ::tavis::kinematics::internal::InvariantFailed(#condition, message, __FILE__, __LINE__); \
    }                                                                                          \
  } while (false)

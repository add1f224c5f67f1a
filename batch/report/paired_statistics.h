// Paired comparison of two protocols on matched episodes (episode i of a head cell and of its fixed
// cell have the same scene): McNemar's exact test on the discordant pairs.
#pragma once

#include <cstdint>

namespace tavis::batch::report {

struct PairedCounts {
  int64_t both = 0;         // succeeded under both protocols
  int64_t first_only = 0;   // succeeded under the first (head) only
  int64_t second_only = 0;  // succeeded under the second (fixed) only
  int64_t neither = 0;

  int64_t pairs() const { return both + first_only + second_only + neither; }
};

// Two-sided exact McNemar p-value: under the null each discordant pair is first_only or
// second_only with probability 1/2, so p = min(1, 2 P[X <= min(b, c)]) for X ~ Binomial(b + c, 1/2).
// 1 when there is no discordant pair.
double McNemarExactP(int64_t first_only, int64_t second_only);

}  // namespace tavis::batch::report

// An anytime-valid paired test on matched episodes, for stopping a pair of cells once its answer
// is known (docs/sweeps.md, "Sequential paired testing"). Under the null each discordant pair
// (exactly one side succeeded) is a fair coin, whatever came before; the e-value is the
// beta-binomial mixture likelihood ratio of the discordant pairs,
//   E(b, c) = B(b + 1/2, c + 1/2) / B(1/2, 1/2) * 2^(b + c),
// b and c the first-only and second-only counts (Jeffreys' Beta(1/2, 1/2) prior on the chance that
// a discordant pair favours the first side). Concordant pairs leave it unchanged. Under the null E
// is a nonnegative martingale starting at 1, so by Ville's inequality P(E ever >= 1/alpha) <= alpha:
// looking after every block of pairs and stopping at the first look with E >= 1/alpha (or at the
// episode cap) decides wrongly with probability at most alpha, however long it runs.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace tavis::batch::report {

struct SequentialTestSettings {
  double alpha = 0.05;  // in (0, 1): the chance of deciding when the two sides are equal
  int block = 10;       // pairs between looks (the sweep runs each paired cell this many episodes at a time)
};

// log E(b, c) as above; 0 with no discordant pair.
double LogDiscordantEValue(int64_t first_only, int64_t second_only);

enum class SequentialOutcome {
  kFirstBetter,   // E >= 1/alpha with more first-only than second-only pairs
  kSecondBetter,  // the same, second-only ahead
  kUndecided,     // the cap came first
};

// "first_better", "second_better", "undecided".
std::string ToString(SequentialOutcome outcome);

struct SequentialDecision {
  SequentialOutcome outcome = SequentialOutcome::kUndecided;
  int64_t pairs = 0;  // the look it decided at (or the pairs there were: the cap)
  int64_t first_only = 0;
  int64_t second_only = 0;
  double e_value = 1.0;  // at that look
};

// The test on the first min(first, second) pairs of the two outcome sequences (success per
// episode, in episode order), looking after every `block` pairs and after the last one: the first
// look whose e-value reaches 1/alpha decides; without one, undecided at the last pair.
SequentialDecision DecideSequentially(const std::vector<bool>& first, const std::vector<bool>& second,
                                      const SequentialTestSettings& settings);

// The looks: block, 2 block, ..., ending with `cap` (the last block may be shorter).
std::vector<int64_t> SequentialLooks(int64_t cap, int block);

}  // namespace tavis::batch::report

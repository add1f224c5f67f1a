#include "batch/report/sequential_test.h"

#include <algorithm>
#include <cmath>

namespace tavis::batch::report {
namespace {

double LogBeta(double a, double b) { return std::lgamma(a) + std::lgamma(b) - std::lgamma(a + b); }

constexpr double kPrior = 0.5;  // Jeffreys: Beta(1/2, 1/2)

}  // namespace

double LogDiscordantEValue(int64_t first_only, int64_t second_only) {
  const double b = static_cast<double>(first_only);
  const double c = static_cast<double>(second_only);
  return LogBeta(b + kPrior, c + kPrior) - LogBeta(kPrior, kPrior) + (b + c) * std::log(2.0);
}

std::string ToString(SequentialOutcome outcome) {
  switch (outcome) {
    case SequentialOutcome::kFirstBetter: return "first_better";
    case SequentialOutcome::kSecondBetter: return "second_better";
    case SequentialOutcome::kUndecided: break;
  }
  return "undecided";
}

std::vector<int64_t> SequentialLooks(int64_t cap, int block) {
  std::vector<int64_t> looks;
  const int64_t step = std::max(1, block);
  for (int64_t n = step; n < cap; n += step) looks.push_back(n);
  if (cap > 0) looks.push_back(cap);
  return looks;
}

SequentialDecision DecideSequentially(const std::vector<bool>& first, const std::vector<bool>& second,
                                      const SequentialTestSettings& settings) {
  const int64_t pairs = static_cast<int64_t>(std::min(first.size(), second.size()));
  const double threshold = -std::log(settings.alpha);
  SequentialDecision decision;
  int64_t counted = 0;
  for (const int64_t look : SequentialLooks(pairs, settings.block)) {
    for (; counted < look; ++counted) {
      const bool a = first[static_cast<std::size_t>(counted)], b = second[static_cast<std::size_t>(counted)];
      if (a && !b) ++decision.first_only;
      if (b && !a) ++decision.second_only;
    }
    decision.pairs = look;
    const double log_e = LogDiscordantEValue(decision.first_only, decision.second_only);
    decision.e_value = std::exp(log_e);
    // A tie never reaches the threshold (its mixture is below 1); the guard keeps the direction honest.
    if (log_e >= threshold && decision.first_only != decision.second_only) {
      decision.outcome = decision.first_only > decision.second_only ? SequentialOutcome::kFirstBetter
                                                                    : SequentialOutcome::kSecondBetter;
      return decision;
    }
  }
  return decision;
}

}  // namespace tavis::batch::report

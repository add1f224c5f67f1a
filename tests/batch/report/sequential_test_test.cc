// The sequential paired test: its e-value against the product of its predictive odds, its looks,
// and its guarantee in simulation: 10,000 seeded null sequences decide at most alpha of the time,
// where McNemar's fixed-n test looked at after every pair does not.
#include "batch/report/sequential_test.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <iostream>
#include <random>
#include <vector>

#include "batch/report/paired_statistics.h"

namespace tavis::batch::report {
namespace {

// E as the product of each discordant pair's predictive probability under the Beta(1/2, 1/2)
// mixture over its probability 1/2 under the null, pair by pair.
double EValueByProducts(const std::vector<bool>& first_wins) {
  double e = 1.0, first = 0.0, second = 0.0;
  for (const bool win : first_wins) {
    const double predictive = ((win ? first : second) + 0.5) / (first + second + 1.0);
    e *= predictive / 0.5;
    (win ? first : second) += 1.0;
  }
  return e;
}

TEST(SequentialTest, EValueIsTheMixturesProductOfPredictiveOdds) {
  EXPECT_NEAR(std::exp(LogDiscordantEValue(7, 0)), EValueByProducts(std::vector<bool>(7, true)), 1e-9);
  const std::vector<bool> mixed = {true, false, true, true, false, true, true, true, false, true};
  EXPECT_NEAR(std::exp(LogDiscordantEValue(7, 3)), EValueByProducts(mixed), 1e-9);
  EXPECT_NEAR(std::exp(LogDiscordantEValue(0, 0)), 1.0, 1e-12);
  // By hand: one discordant pair either way is a fair bet, E = (1/2 / 1) / (1/2).
  EXPECT_NEAR(std::exp(LogDiscordantEValue(1, 0)), 1.0, 1e-12);
  EXPECT_NEAR(std::exp(LogDiscordantEValue(2, 0)), 1.5, 1e-12);  // * (1.5 / 2) / (1/2)
  EXPECT_LT(LogDiscordantEValue(5, 5), 0.0) << "a tie is evidence for the null";
}

TEST(SequentialTest, LooksAfterEveryBlockAndAtTheCap) {
  EXPECT_EQ(SequentialLooks(25, 10), (std::vector<int64_t>{10, 20, 25}));
  EXPECT_EQ(SequentialLooks(20, 10), (std::vector<int64_t>{10, 20}));
  EXPECT_EQ(SequentialLooks(3, 1), (std::vector<int64_t>{1, 2, 3}));
  EXPECT_TRUE(SequentialLooks(0, 5).empty());
}

// A side that always wins (the expert against hold) decides after 7 discordant pairs at alpha
// 0.05 (E(6, 0) = 14.7 < 20 <= E(7, 0) = 27.3), so at the first look after them.
TEST(SequentialTest, OneSidedPairsDecideAtTheFirstLookPastSevenDiscordantPairs) {
  const std::vector<bool> always(40, true), never(40, false);
  SequentialDecision decision = DecideSequentially(always, never, {0.05, 1});
  EXPECT_EQ(decision.outcome, SequentialOutcome::kFirstBetter);
  EXPECT_EQ(decision.pairs, 7);
  EXPECT_EQ(decision.first_only, 7);
  EXPECT_GE(decision.e_value, 20.0);
  decision = DecideSequentially(never, always, {0.05, 5});
  EXPECT_EQ(decision.outcome, SequentialOutcome::kSecondBetter);
  EXPECT_EQ(decision.pairs, 10);
  EXPECT_EQ(decision.second_only, 10);
  // Both succeeding every time is no evidence: undecided at the last pair.
  decision = DecideSequentially(always, always, {0.05, 5});
  EXPECT_EQ(decision.outcome, SequentialOutcome::kUndecided);
  EXPECT_EQ(decision.pairs, 40);
  EXPECT_DOUBLE_EQ(decision.e_value, 1.0);
  // Only the pairs both sides have count.
  decision = DecideSequentially(always, std::vector<bool>(6, false), {0.05, 1});
  EXPECT_EQ(decision.outcome, SequentialOutcome::kUndecided);
  EXPECT_EQ(decision.pairs, 6);
}

// One pair sequence: per pair both succeed, neither, first only or second only, with the
// chances given, drawn from `random` (raw 64-bit draws: the same sequence on every standard library).
struct PairChances {
  double both, neither, first_only;  // second_only: the rest
};

void DrawPairs(std::mt19937_64& random, const PairChances& chances, int count, std::vector<bool>& first,
               std::vector<bool>& second) {
  first.clear();
  second.clear();
  for (int i = 0; i < count; ++i) {
    const double u = static_cast<double>(random() >> 11) * 0x1.0p-53;
    const bool both = u < chances.both;
    const bool neither = !both && u < chances.both + chances.neither;
    const bool first_only = !both && !neither && u < chances.both + chances.neither + chances.first_only;
    first.push_back(both || first_only);
    second.push_back(both || (!neither && !first_only));
  }
}

struct NullRates {
  int sequential = 0;        // decided
  int repeated_mcnemar = 0;  // McNemar's p < alpha at some look
};

NullRates CountNullDecisions(const PairChances& chances, int sequences, int cap, int block, double alpha) {
  std::mt19937_64 random(20261202);
  NullRates rates;
  // McNemar's p for every count the sequences can reach, computed once.
  std::vector<std::vector<double>> mcnemar(cap + 1, std::vector<double>(cap + 1, 1.0));
  for (int b = 0; b <= cap; ++b) {
    for (int c = 0; b + c <= cap; ++c) mcnemar[b][c] = McNemarExactP(b, c);
  }
  std::vector<bool> first, second;
  for (int s = 0; s < sequences; ++s) {
    DrawPairs(random, chances, cap, first, second);
    if (DecideSequentially(first, second, {alpha, block}).outcome != SequentialOutcome::kUndecided) ++rates.sequential;
    int64_t b = 0, c = 0;
    for (int i = 0; i < cap; ++i) {
      b += first[i] && !second[i];
      c += second[i] && !first[i];
      if ((i + 1) % block == 0 && mcnemar[b][c] < alpha) {
        ++rates.repeated_mcnemar;
        break;
      }
    }
  }
  return rates;
}

// The acceptance check: 10,000 null sequences of 96 pairs, a look after every pair (the most
// looks, the most chances to be fooled), alpha 0.05: at most 500 decide. Peeking at McNemar's
// fixed-n p after every pair is fooled more often than alpha in the same sequences, so the
// simulation can tell a valid sequential test from an invalid one.
TEST(SequentialTest, NullSequencesDecideAtMostAlphaOfTheTime) {
  constexpr int kSequences = 10000;
  const PairChances null{0.3, 0.3, 0.2};  // discordant pairs fair coins
  const NullRates every_pair = CountNullDecisions(null, kSequences, 96, 1, 0.05);
  std::cout << "null sequences deciding, a look after every pair: sequential " << every_pair.sequential << " of "
            << kSequences << ", McNemar looked at as often " << every_pair.repeated_mcnemar << "\n";
  EXPECT_LE(every_pair.sequential, 0.05 * kSequences) << every_pair.sequential << " of " << kSequences;
  EXPECT_GT(every_pair.repeated_mcnemar, 0.05 * kSequences)
      << "peeking at McNemar after every pair should exceed alpha: " << every_pair.repeated_mcnemar;
  // The sweep's default block, and a stricter level with every pair discordant.
  const NullRates blocks = CountNullDecisions(null, kSequences, 96, 10, 0.05);
  std::cout << "a look every 10 pairs: sequential " << blocks.sequential << " of " << kSequences << "\n";
  EXPECT_LE(blocks.sequential, 0.05 * kSequences) << blocks.sequential;
  const NullRates strict = CountNullDecisions({0.0, 0.0, 0.5}, kSequences, 200, 1, 0.01);
  std::cout << "every pair discordant, 200 pairs, alpha 0.01: " << strict.sequential << " of " << kSequences << "\n";
  EXPECT_LE(strict.sequential, 0.01 * kSequences) << strict.sequential;
}

// Not a test that never decides: a real difference (first only 4 times as often) is found in most
// sequences, mostly well before the cap.
TEST(SequentialTest, RealDifferencesAreDecidedInTheirDirection) {
  std::mt19937_64 random(7);
  std::vector<bool> first, second;
  int first_better = 0, second_better = 0;
  for (int s = 0; s < 1000; ++s) {
    DrawPairs(random, {0.3, 0.3, 0.32}, 96, first, second);
    const SequentialOutcome outcome = DecideSequentially(first, second, {0.05, 10}).outcome;
    first_better += outcome == SequentialOutcome::kFirstBetter;
    second_better += outcome == SequentialOutcome::kSecondBetter;
  }
  EXPECT_GT(first_better, 800);
  EXPECT_LT(second_better, 10);
}

}  // namespace
}  // namespace tavis::batch::report

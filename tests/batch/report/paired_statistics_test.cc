// McNemar's exact test and the Wilson interval on examples computed by hand.
#include "batch/report/paired_statistics.h"

#include <gtest/gtest.h>

#include "batch/cell/statistics.h"

namespace tavis::batch::report {
namespace {

TEST(McNemarExact, MatchesTheBinomialTailComputedByHand) {
  // b = 1, c = 6: n = 7, P[X <= 1] = (C(7,0) + C(7,1)) / 2^7 = 8 / 128, p = 2 * 8 / 128.
  EXPECT_NEAR(McNemarExactP(1, 6), 0.125, 1e-12);
  EXPECT_NEAR(McNemarExactP(6, 1), 0.125, 1e-12);
  // b = 3, c = 10: (1 + 13 + 78 + 286) / 8192 = 378 / 8192, p = 756 / 8192.
  EXPECT_NEAR(McNemarExactP(3, 10), 756.0 / 8192.0, 1e-12);
  // All discordant pairs one way, n = 5: p = 2 / 32.
  EXPECT_NEAR(McNemarExactP(0, 5), 0.0625, 1e-12);
}

TEST(McNemarExact, IsOneWithoutEvidence) {
  EXPECT_EQ(McNemarExactP(0, 0), 1.0);
  EXPECT_EQ(McNemarExactP(5, 5), 1.0);  // 2 * 638/1024 capped at 1
}

TEST(McNemarExact, StaysFiniteForLargeCounts) {
  // 2^-2000 underflows; the log-space sum must still give a tiny positive p and a p near 1 when balanced.
  const double p = McNemarExactP(900, 1100);
  EXPECT_GT(p, 0.0);
  EXPECT_LT(p, 1e-4);
  EXPECT_GT(McNemarExactP(1000, 1001), 0.9);
}

TEST(WilsonInterval, MatchesTheScoreIntervalComputedByHand) {
  // 7/10, z = 1.96: centre (0.7 + 0.19208) / 1.38416, half-width 1.96 / 1.38416 * sqrt(0.021 + 0.0009604).
  const cell::ProportionInterval interval = cell::WilsonInterval(7, 10);
  EXPECT_NEAR(interval.low, 0.396773, 1e-6);
  EXPECT_NEAR(interval.high, 0.892211, 1e-6);
  const cell::ProportionInterval none = cell::WilsonInterval(0, 10);
  EXPECT_NEAR(none.low, 0.0, 1e-12);
  EXPECT_NEAR(none.high, 0.277540, 1e-6);
}

}  // namespace
}  // namespace tavis::batch::report

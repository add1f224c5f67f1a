#include "batch/cell/statistics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace tavis::batch::cell {
namespace {

// Percent rounded to 0.1, as the paper prints intervals.
double RoundedPercent(double fraction) { return std::round(fraction * 1000.0) / 10.0; }

void ExpectInterval(int successes, int trials, double low_percent, double high_percent) {
  const ProportionInterval interval = WilsonInterval(successes, trials);
  EXPECT_DOUBLE_EQ(RoundedPercent(interval.low), low_percent) << successes << "/" << trials;
  EXPECT_DOUBLE_EQ(RoundedPercent(interval.high), high_percent) << successes << "/" << trials;
}

// The paper's figures (reference spec 14): a cell, an empty cell, a pooled suite mean.
TEST(WilsonInterval, MatchesThePaper) {
  ExpectInterval(84, 96, 79.4, 92.7);
  ExpectInterval(0, 96, 0.0, 3.8);
  ExpectInterval(226, 480, 42.7, 51.6);
}

TEST(WilsonInterval, StaysInsideTheUnitIntervalAndContainsTheRate) {
  for (int successes = 0; successes <= 20; ++successes) {
    const ProportionInterval interval = WilsonInterval(successes, 20);
    EXPECT_GE(interval.low, 0.0);
    EXPECT_LE(interval.high, 1.0);
    EXPECT_LE(interval.low, successes / 20.0);
    EXPECT_GE(interval.high, successes / 20.0);
  }
  EXPECT_DOUBLE_EQ(WilsonInterval(20, 20).high, 1.0);
}

TEST(WilsonInterval, WiderZGivesAWiderInterval) {
  const ProportionInterval z196 = WilsonInterval(30, 60);
  const ProportionInterval z258 = WilsonInterval(30, 60, 2.576);
  EXPECT_LT(z258.low, z196.low);
  EXPECT_GT(z258.high, z196.high);
}

// Values worked by hand: 2, 4, 4, 4, 5, 5, 7, 9 has mean 5, population std 2 (numpy's std) and
// median 4.5 (the middle two's mean); order does not matter.
TEST(SpreadOf, MeanMedianAndPopulationStd) {
  const Spread spread = SpreadOf({9.0, 4.0, 2.0, 5.0, 4.0, 7.0, 4.0, 5.0});
  EXPECT_EQ(spread.n, 8u);
  EXPECT_DOUBLE_EQ(spread.mean, 5.0);
  EXPECT_DOUBLE_EQ(spread.median, 4.5);
  EXPECT_DOUBLE_EQ(spread.std, 2.0);
}

TEST(SpreadOf, OddCountTakesTheMiddleValueAndOneValueHasNoSpread) {
  EXPECT_DOUBLE_EQ(Median({3.0, 1.0, 2.0}), 2.0);
  const Spread one = SpreadOf({1.5});
  EXPECT_DOUBLE_EQ(one.mean, 1.5);
  EXPECT_DOUBLE_EQ(one.median, 1.5);
  EXPECT_DOUBLE_EQ(one.std, 0.0);
}

TEST(SpreadOf, NoValuesIsRefused) {
  EXPECT_THROW(SpreadOf({}), std::invalid_argument);
  EXPECT_THROW(Median({}), std::invalid_argument);
  EXPECT_THROW(Quantile({}, 0.5), std::invalid_argument);
}

// numpy.quantile([2, 4, 4, 4, 5, 5, 7, 9], [0, 0.25, 0.5, 0.75, 1]) = 2, 4, 4.5, 5.5, 9 (linear);
// of [1, 2, 3, 4]: q 0.25 is 1.75.
TEST(Quantile, InterpolatesLinearlyBetweenOrderStatisticsAsNumpy) {
  const std::vector<double> values = {9.0, 4.0, 2.0, 5.0, 4.0, 7.0, 4.0, 5.0};
  EXPECT_DOUBLE_EQ(Quantile(values, 0.0), 2.0);
  EXPECT_DOUBLE_EQ(Quantile(values, 0.25), 4.0);
  EXPECT_DOUBLE_EQ(Quantile(values, 0.5), Median(values));
  EXPECT_DOUBLE_EQ(Quantile(values, 0.75), 5.5);
  EXPECT_DOUBLE_EQ(Quantile(values, 1.0), 9.0);
  EXPECT_DOUBLE_EQ(Quantile({4.0, 1.0, 3.0, 2.0}, 0.25), 1.75);
  EXPECT_DOUBLE_EQ(Quantile({2.5}, 0.75), 2.5);
}

}  // namespace
}  // namespace tavis::batch::cell

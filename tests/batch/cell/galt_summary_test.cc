#include "batch/cell/galt_summary.h"

#include <gtest/gtest.h>

#include <cmath>

namespace tavis::batch::cell {
namespace {

using kinematics::GaltReason;
using kinematics::GaltResult;

GaltResult Valid(double galt_s, GaltReason reason = GaltReason::kOk) {
  GaltResult result;
  result.galt_s = galt_s;
  result.reason = reason;
  result.arm = kinematics::Side::kRight;
  return result;
}

GaltResult Invalid(GaltReason reason) {
  GaltResult result;
  result.reason = reason;
  return result;
}

TEST(GaltSummary, StatisticsOverValidValuesAndCountsOverAll) {
  const GaltSummary summary =
      SummarizeGalt({Valid(1.0), Valid(2.0, GaltReason::kOkPostAnchor), Valid(4.0), Invalid(GaltReason::kNoFixation),
                     Invalid(GaltReason::kNoFixation), Invalid(GaltReason::kTooShort), Valid(3.0)});
  EXPECT_EQ(summary.n_episodes, 7);
  EXPECT_EQ(summary.n_valid, 4);
  EXPECT_DOUBLE_EQ(*summary.mean_s, 2.5);
  EXPECT_DOUBLE_EQ(*summary.median_s, 2.5);  // even count: mean of 2.0 and 3.0
  // Population standard deviation (divisor n): sqrt((2.25 + 0.25 + 0.25 + 2.25) / 4).
  EXPECT_DOUBLE_EQ(*summary.std_s, std::sqrt(1.25));
  EXPECT_EQ(summary.count(GaltReason::kOk), 3);
  EXPECT_EQ(summary.count(GaltReason::kOkPostAnchor), 1);
  EXPECT_EQ(summary.count(GaltReason::kNoFixation), 2);
  EXPECT_EQ(summary.count(GaltReason::kTooShort), 1);
  EXPECT_EQ(summary.count(GaltReason::kAmbiguousArms), 0);
}

TEST(GaltSummary, OddCountMedianIsTheMiddleValue) {
  const GaltSummary summary = SummarizeGalt({Valid(3.0), Valid(-0.2), Valid(10.0)});
  EXPECT_DOUBLE_EQ(*summary.median_s, 3.0);
  EXPECT_DOUBLE_EQ(*summary.mean_s, 12.8 / 3.0);
}

TEST(GaltSummary, NoValidValuesLeavesStatisticsAbsent) {
  const GaltSummary summary = SummarizeGalt({Invalid(GaltReason::kNoGrasp)});
  EXPECT_EQ(summary.n_episodes, 1);
  EXPECT_EQ(summary.n_valid, 0);
  EXPECT_FALSE(summary.mean_s.has_value());
  EXPECT_FALSE(summary.median_s.has_value());
  EXPECT_FALSE(summary.std_s.has_value());
  EXPECT_EQ(summary.count(GaltReason::kNoGrasp), 1);

  const GaltSummary empty = SummarizeGalt({});
  EXPECT_EQ(empty.n_episodes, 0);
  EXPECT_FALSE(empty.mean_s.has_value());
}

}  // namespace
}  // namespace tavis::batch::cell

#include "kinematics/action_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace tavis::kinematics {
namespace {

Action Reasonable() {
  Action action{};
  action[action::kArmPosition[0]] = 0.3;
  action[action::kArmPosition[1]] = 0.3;
  action[action::kArmQuaternion[0]] = 1.0;
  action[action::kArmQuaternion[1]] = 1.0;
  action[action::kGripper[0]] = -1.0;
  return action;
}

TEST(ActionCheck, AcceptsAnOrdinaryActionAndAnUnnormalisedQuaternion) {
  Action action = Reasonable();
  EXPECT_FALSE(FindActionDefect(action).found());
  action[action::kArmQuaternion[1]] = 7.0;  // normalised by the IK
  action[action::kNeckYaw] = 1e300;         // clamped to the joint's range
  EXPECT_FALSE(FindActionDefect(action).found());
}

TEST(ActionCheck, NamesTheFirstNonFiniteEntry) {
  Action action = Reasonable();
  action[action::kNeckPitch] = std::numeric_limits<double>::quiet_NaN();
  action[action::kGripper[1]] = std::numeric_limits<double>::infinity();
  const ActionDefect defect = FindActionDefect(action);
  EXPECT_EQ(defect.entry, action::kNeckPitch);
  EXPECT_TRUE(std::isnan(defect.value));
  EXPECT_STREQ(defect.reason, "not finite");
}

TEST(ActionCheck, NamesAFarTargetAHugeQuaternionAndAZeroQuaternion) {
  Action far = Reasonable();
  far[action::kArmPosition[1] + 2] = -1e20;
  EXPECT_EQ(FindActionDefect(far).entry, action::kArmPosition[1] + 2);
  EXPECT_EQ(FindActionDefect(far).value, -1e20);

  Action huge = Reasonable();
  huge[action::kArmQuaternion[0] + 1] = 1e308;
  EXPECT_EQ(FindActionDefect(huge).entry, action::kArmQuaternion[0] + 1);

  Action zero = Reasonable();
  for (int k = 0; k < 4; ++k) zero[action::kArmQuaternion[1] + k] = 0.0;
  const ActionDefect defect = FindActionDefect(zero);
  EXPECT_EQ(defect.entry, action::kArmQuaternion[1]);
  EXPECT_STREQ(defect.reason, "zero quaternion (norm below 1e-6)");
}

TEST(ActionCheck, TheBoundsThemselvesAreAccepted) {
  Action action = Reasonable();
  action[action::kArmPosition[0]] = kMaxTargetCoordinate;
  EXPECT_FALSE(FindActionDefect(action).found());
  action[action::kArmPosition[0]] = std::nextafter(kMaxTargetCoordinate, 1e9);
  EXPECT_TRUE(FindActionDefect(action).found());
}

}  // namespace
}  // namespace tavis::kinematics

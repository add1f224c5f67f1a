#include "scenarios/expert/arm_reach.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "kinematics/forward_kinematics.h"
#include "scenarios/expert/arm_planner.h"
#include "tests/support/robot_loading.h"

namespace tavis::scenarios::expert {
namespace {

class ArmReachTest : public ::testing::TestWithParam<std::string> {};

// The planner gives up on a target outside the sphere without iterating: no configuration may
// put the hand outside it, and the sphere must not be much larger than the arm's real reach.
TEST_P(ArmReachTest, EveryConfigurationKeepsTheHandInsideTheSphereAndSomeComeNearItsEdge) {
  const kinematics::RobotModel robot = tavis::testing::LoadRobot(GetParam());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<RigidTransform> X_BL(robot.links.size());
  for (const kinematics::Side side : kinematics::kSides) {
    std::vector<double> q = robot.DefaultPositions();
    kinematics::ComputeLinkPoses(robot, q.data(), X_BL.data());
    const ArmReach at_default = ArmReachOf(robot, side, X_BL.data());
    double farthest = 0.0;
    for (int trial = 0; trial < 5000; ++trial) {
      for (const int j : robot.arm(side).joints) {
        const kinematics::Joint& joint = robot.joints[static_cast<std::size_t>(j)];
        q[static_cast<std::size_t>(j)] = joint.lower + unit(rng) * (joint.upper - joint.lower);
      }
      kinematics::ComputeLinkPoses(robot, q.data(), X_BL.data());
      const ArmReach reach = ArmReachOf(robot, side, X_BL.data());
      ASSERT_EQ(reach.centre, at_default.centre) << "the arm's joints moved the centre";
      ASSERT_EQ(reach.radius, at_default.radius);
      const double distance =
          (X_BL[static_cast<std::size_t>(robot.arm(side).ik_link)].translation() - reach.centre).norm();
      ASSERT_LE(distance, reach.radius);
      farthest = std::max(farthest, distance);
    }
    EXPECT_GT(farthest, 0.85 * at_default.radius);
  }
}

// A hand target 1 cm beyond the sphere finds no configuration; 1 cm inside, straight out from the
// shoulder in the direction the hand points at the default pose, it is still reached.
TEST_P(ArmReachTest, PlannerRefusesTargetsBeyondTheSphere) {
  const kinematics::RobotModel robot = tavis::testing::LoadRobot(GetParam());
  const std::vector<double> q = robot.DefaultPositions();
  std::vector<RigidTransform> X_BL(robot.links.size());
  kinematics::ComputeLinkPoses(robot, q.data(), X_BL.data());
  for (const kinematics::Side side : kinematics::kSides) {
    const ArmReach reach = ArmReachOf(robot, side, X_BL.data());
    const RigidTransform& X_B_hand = X_BL[static_cast<std::size_t>(robot.arm(side).ik_link)];
    const Vec3 direction = (X_B_hand.translation() - reach.centre).normalized();
    const Quat orientation(X_B_hand.linear());
    EXPECT_FALSE(SolveArmConfiguration(robot, side, q, {reach.centre + (reach.radius + 0.01) * direction, orientation})
                     .has_value());
    EXPECT_TRUE(SolveArmConfiguration(robot, side, q, {reach.centre + 0.5 * reach.radius * direction, orientation})
                    .has_value());
  }
}

INSTANTIATE_TEST_SUITE_P(Robots, ArmReachTest, ::testing::Values("gr1t2", "reachy2"));

}  // namespace
}  // namespace tavis::scenarios::expert

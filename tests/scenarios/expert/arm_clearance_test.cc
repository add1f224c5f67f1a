#include "scenarios/expert/arm_clearance.h"

#include <gtest/gtest.h>

#include <vector>

#include "kinematics/forward_kinematics.h"
#include "scenarios/expert/arm_planner.h"
#include "scenarios/registry.h"
#include "tests/support/robot_loading.h"

namespace tavis::scenarios::expert {
namespace {

OrientedBox Box(const Vec3& centre, const Vec3& half_size, double yaw = 0.0) {
  return {MakeTransform(centre, Eigen::AngleAxisd(yaw, Vec3::UnitZ()).toRotationMatrix()), half_size};
}

TEST(BoxesOverlap, FaceSeparationAndMargin) {
  const OrientedBox a = Box(Vec3::Zero(), Vec3::Constant(0.1));
  EXPECT_TRUE(BoxesOverlap(a, Box(Vec3(0.15, 0.0, 0.0), Vec3::Constant(0.1)), 0.0));
  EXPECT_FALSE(BoxesOverlap(a, Box(Vec3(0.21, 0.0, 0.0), Vec3::Constant(0.1)), 0.0));
  // 1 cm apart: clear without a margin, too close with 2 cm.
  EXPECT_TRUE(BoxesOverlap(a, Box(Vec3(0.21, 0.0, 0.0), Vec3::Constant(0.1)), 0.02));
}

TEST(BoxesOverlap, RotatedBoxSeparatedOnlyAlongItsOwnFace) {
  // A box of half size 0.1 turned 45 degrees reaches 0.1414 along x and y, so at (0.23, 0.23)
  // the boxes overlap along both world axes and are separated only along the turned box's face
  // normal (0.325 apart, 0.241 of extent); at (0.16, 0.16) they overlap (0.226).
  const OrientedBox a = Box(Vec3::Zero(), Vec3::Constant(0.1));
  const OrientedBox turned = Box(Vec3(0.23, 0.23, 0.0), Vec3::Constant(0.1), M_PI / 4);
  EXPECT_FALSE(BoxesOverlap(a, turned, 0.0));
  EXPECT_TRUE(BoxesOverlap(a, Box(Vec3(0.16, 0.16, 0.0), Vec3::Constant(0.1), M_PI / 4), 0.0));
}

// occluded-reach's monitor is an obstacle for the arm; the table is not.
TEST(ArmObstacles, DefaultPoseIsClearAndAHandThroughTheScreenIsNot) {
  const ScenarioDef& scenario = FindScenario("occluded-reach");
  engine::WorldModel model;
  model.robot = tavis::testing::LoadRobot("gr1t2");
  scenario.layout(model);
  engine::BatchState state;
  state.Allocate(1, model.robot.num_joints(), model.num_objects());
  const ArmObstacles obstacles(model, state, 0, 0.01);
  ASSERT_FALSE(obstacles.empty());
  std::vector<double> q = model.robot.DefaultPositions();
  std::vector<RigidTransform> X_BL(model.robot.links.size());
  kinematics::ComputeLinkPoses(model.robot, q.data(), X_BL.data());
  for (const kinematics::Side side : kinematics::kSides)
    EXPECT_TRUE(obstacles.ArmIsClear(model.robot, side, X_BL.data()));

  // The planner finds a left arm configuration with the hand inside the panel (x 0.27, y 0,
  // z 1.3), in the default hand orientation, unless told to keep clear of the obstacles.
  const kinematics::Side left = kinematics::Side::kLeft;
  const RigidTransform X_B_hand = X_BL[static_cast<std::size_t>(model.robot.arm(left).ik_link)];
  const kinematics::PoseTarget in_panel{Vec3(0.27, 0.0, 1.30) - model.robot.root_world, Quat(X_B_hand.linear())};
  const auto q_through = SolveArmConfiguration(model.robot, left, q, in_panel);
  ASSERT_TRUE(q_through.has_value());
  kinematics::ComputeLinkPoses(model.robot, q_through->data(), X_BL.data());
  EXPECT_FALSE(obstacles.ArmIsClear(model.robot, left, X_BL.data()));
  EXPECT_FALSE(SolveArmConfiguration(model.robot, left, q, in_panel, &obstacles).has_value());
}

}  // namespace
}  // namespace tavis::scenarios::expert

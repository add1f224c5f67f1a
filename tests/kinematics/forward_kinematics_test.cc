#include "kinematics/forward_kinematics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "tests/kinematics/robot_fixture.h"

namespace tavis::kinematics {
namespace {

using ::tavis::testing::LoadRobot;
using testing::LinkPoses;

// robots-kinematics.md 1.6: TAVIS's default pose puts the wrist at the teleop rest position.
TEST(ForwardKinematics, Gr1t2DefaultPoseMatchesReference) {
  const RobotModel robot = LoadRobot("gr1t2");
  const auto X_BL = LinkPoses(robot, robot.DefaultPositions());
  const Vec3 left = X_BL[robot.LinkIndex("left_hand_pitch_link")].translation();
  const Vec3 right = X_BL[robot.LinkIndex("right_hand_pitch_link")].translation();
  EXPECT_NEAR((left - Vec3(0.3005, 0.2000, 0.2997)).norm(), 0.0, 1e-3) << left.transpose();
  EXPECT_NEAR((right - Vec3(0.3005, -0.2001, 0.2997)).norm(), 0.0, 1e-3) << right.transpose();
  const Quat q_left(X_BL[robot.LinkIndex("left_hand_pitch_link")].linear());
  EXPECT_LT(q_left.angularDistance(Quat(0.505, -0.042, -0.862, -0.024).normalized()), 2e-3);
}

TEST(ForwardKinematics, Gr1t2HeadCameraAtZeroPose) {
  const RobotModel robot = LoadRobot("gr1t2");
  const auto X_BL = LinkPoses(robot, std::vector<double>(robot.num_joints(), 0.0));
  const RigidTransform X_BC = CameraPose(robot, robot.CameraIndex("head"), X_BL.data());
  const Vec3 world = X_BC.translation() + robot.root_world;
  EXPECT_NEAR((world - Vec3(0.105, 0.0006, 1.454)).norm(), 0.0, 1e-3) << world.transpose();
  EXPECT_NEAR((X_BC.linear() * Vec3::UnitX() - Vec3::UnitX()).norm(), 0.0, 1e-9);
}

// reachy2.yaml fk_tests, expressed in the torso frame (independent of the torso lift).
TEST(ForwardKinematics, Reachy2DefaultPalmInTorsoFrame) {
  const RobotModel robot = LoadRobot("reachy2");
  const auto X_BL = LinkPoses(robot, robot.DefaultPositions());
  const RigidTransform X_TB = X_BL[robot.LinkIndex("torso")].inverse();
  const RigidTransform X_TP = X_TB * X_BL[robot.LinkIndex("l_hand_palm_link")];
  EXPECT_NEAR((X_TP.translation() - Vec3(0.339, 0.1799, -0.1458)).norm(), 0.0, 1e-3) << X_TP.translation().transpose();
  EXPECT_LT(Quat(X_TP.linear()).angularDistance(Quat(0.0025, 0.5241, -0.1561, 0.8372).normalized()), 2e-3);
  const RigidTransform X_TR = X_TB * X_BL[robot.LinkIndex("r_hand_palm_link")];
  EXPECT_NEAR((X_TR.translation() - Vec3(0.339, -0.1799, -0.1458)).norm(), 0.0, 1e-3);
}

TEST(ForwardKinematics, Reachy2HeadCameraLooksTenDegreesDown) {
  const RobotModel robot = LoadRobot("reachy2");
  const auto X_BL = LinkPoses(robot, std::vector<double>(robot.num_joints(), 0.0));
  const RigidTransform X_TB = X_BL[robot.LinkIndex("torso")].inverse();
  const RigidTransform X_TC = X_TB * CameraPose(robot, robot.CameraIndex("head"), X_BL.data());
  EXPECT_NEAR((X_TC.translation() - Vec3(0.0284, 0.0, 0.1608)).norm(), 0.0, 1e-3);
  EXPECT_NEAR((X_TC.linear() * Vec3::UnitX() - Vec3(0.985, 0.0, -0.174)).norm(), 0.0, 2e-3);
}

// Moving one arm's joints and recomputing only the links below its shoulder gives every link the
// pose a full pass gives.
// The planner moves one arm's joints and recomputes only LinksMovedByArm: the poses must equal
// a full pass bit for bit, or planning (and so every record) would change.
TEST(ForwardKinematics, PosesOfTheLinksAnArmMovesEqualAFullPassExactly) {
  std::mt19937 rng(3);
  for (const char* name : {"gr1t2", "reachy2"}) {
    const RobotModel robot = LoadRobot(name);
    for (Side side : kSides) {
      const ArmSpec& arm = robot.arm(side);
      const std::vector<int> moved = LinksMovedByArm(robot, side);
      ASSERT_GE(moved.size(), static_cast<size_t>(kArmDof)) << name;
      EXPECT_TRUE(std::is_sorted(moved.begin(), moved.end()));
      EXPECT_NE(std::find(moved.begin(), moved.end(), arm.ik_link), moved.end()) << name;
      std::vector<double> q = robot.DefaultPositions();
      std::vector<RigidTransform> X_BL = LinkPoses(robot, q);
      const std::vector<RigidTransform> before = X_BL;
      for (int joint : arm.joints) {
        std::uniform_real_distribution<double> within(robot.joints[joint].lower, robot.joints[joint].upper);
        q[joint] = within(rng);
      }
      ComputeLinkPosesOf(robot, q.data(), moved, X_BL.data());
      const std::vector<RigidTransform> full = LinkPoses(robot, q);
      for (int i = 0; i < robot.num_links(); ++i) {
        EXPECT_EQ(X_BL[i].matrix(), full[i].matrix()) << name << " link " << robot.links[i].name;
        const bool listed = std::find(moved.begin(), moved.end(), i) != moved.end();
        if (!listed) {
          EXPECT_EQ(before[i].matrix(), full[i].matrix()) << "an unlisted link moved: " << robot.links[i].name;
        }
      }
    }
  }
}

TEST(ForwardKinematics, ALinksChainAloneGivesItsFullPassPoseExactly) {
  std::mt19937 rng(5);
  for (const char* name : {"gr1t2", "reachy2"}) {
    const RobotModel robot = LoadRobot(name);
    std::vector<double> q = robot.DefaultPositions();
    for (int j = 0; j < robot.num_joints(); ++j) {
      std::uniform_real_distribution<double> within(robot.joints[j].lower, robot.joints[j].upper);
      q[j] = within(rng);
    }
    const std::vector<RigidTransform> full = LinkPoses(robot, q);
    for (int link : {robot.cameras[robot.CameraIndex("head")].link, robot.arm(Side::kLeft).ik_link,
                     robot.arm(Side::kRight).ik_link}) {
      std::vector<RigidTransform> X_BL(robot.links.size(), RigidTransform::Identity());
      ComputeLinkPoseChain(robot, q.data(), link, X_BL.data());
      EXPECT_EQ(X_BL[link].matrix(), full[link].matrix()) << name << " link " << robot.links[link].name;
    }
  }
}

class JacobianTest : public ::testing::TestWithParam<std::tuple<std::string, Side>> {};

TEST_P(JacobianTest, MatchesFiniteDifferences) {
  const auto& [robot_name, side] = GetParam();
  const RobotModel robot = LoadRobot(robot_name);
  const ArmSpec& arm = robot.arm(side);
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<double> q = robot.DefaultPositions();
    for (int j = 0; j < robot.num_joints(); ++j) {
      std::uniform_real_distribution<double> within(robot.joints[j].lower, robot.joints[j].upper);
      q[j] = within(rng);
    }
    const auto X_BL = LinkPoses(robot, q);
    const ArmJacobian J = ComputeArmJacobian(robot, side, X_BL.data());
    const double h = 1e-6;
    for (int column = 0; column < kArmDof; ++column) {
      std::vector<double> q_plus = q;
      q_plus[arm.joints[column]] += h;
      const auto X_plus = LinkPoses(robot, q_plus);
      const RigidTransform& a = X_BL[arm.ik_link];
      const RigidTransform& b = X_plus[arm.ik_link];
      const Vec3 linear = (b.translation() - a.translation()) / h;
      const Vec3 angular = AxisAngleVector(Quat(b.linear()) * Quat(a.linear()).inverse()) / h;
      EXPECT_NEAR((linear - J.block<3, 1>(0, column)).norm(), 0.0, 1e-5) << "column " << column;
      EXPECT_NEAR((angular - J.block<3, 1>(3, column)).norm(), 0.0, 1e-5) << "column " << column;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(BothRobotsBothArms, JacobianTest,
                         ::testing::Combine(::testing::Values("gr1t2", "reachy2"),
                                            ::testing::Values(Side::kLeft, Side::kRight)));

}  // namespace
}  // namespace tavis::kinematics

#include "batch/proprioception.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "batch/vec_env.h"
#include "kinematics/forward_kinematics.h"
#include "scenarios/registry.h"
#include "tests/support/robot_loading.h"

namespace tavis::batch {
namespace {

class Proprioception : public ::testing::TestWithParam<std::string> {
 protected:
  Proprioception()
      : robot_(tavis::testing::LoadRobot(GetParam())),
        env_(BuildWorldModel(robot_, scenarios::FindScenario("clutter-pick-cube")),
             scenarios::FindScenario("clutter-pick-cube"), scenarios::Split::kOodInitPose, 2, 3) {
    // ood-init-pose's warm-up leaves the neck and the arms away from their defaults.
    env_.ResetEnv(0, 1);
    env_.ResetEnv(1, 2);
  }
  kinematics::RobotModel robot_;
  VecEnv env_;
};

TEST_P(Proprioception, StateEntriesReadTheirJointsGripperGapsAndConstants) {
  ProprioceptionBatch proprioception(env_.model().robot, 2);
  proprioception.Update(env_.state(), {0, 1});
  const engine::BatchState& state = env_.state();
  const float* row = proprioception.state(1);
  ASSERT_EQ(proprioception.state_size(), static_cast<int>(robot_.observation_state.size()));
  int joints = 0;
  for (int entry = 0; entry < proprioception.state_size(); ++entry) {
    const kinematics::StateEntry& spec = robot_.observation_state[static_cast<std::size_t>(entry)];
    switch (spec.kind) {
      case kinematics::StateEntry::Kind::kJoint:
        EXPECT_EQ(row[entry], static_cast<float>(state.q_row(1)[spec.joint])) << spec.name;
        ++joints;
        break;
      case kinematics::StateEntry::Kind::kUnsimulated: EXPECT_EQ(row[entry], 0.0f) << spec.name; break;
      case kinematics::StateEntry::Kind::kGripperGap:
        EXPECT_EQ(row[entry], static_cast<float>(state.gripper_gap_row(1)[kinematics::Index(spec.side)]));
        EXPECT_GT(row[entry], 0.05f) << "the gripper starts open";
        break;
    }
  }
  EXPECT_EQ(joints, robot_.num_joints());
  for (int entry : proprioception.neck_entries()) ASSERT_GE(entry, 0);
  EXPECT_GT(std::abs(row[proprioception.neck_entries()[1]]) + std::abs(row[proprioception.neck_entries()[2]]), 1e-3f)
      << "the warm-up moved the neck";
  const float* untouched = proprioception.state(0);
  for (int entry = 0; entry < proprioception.state_size(); ++entry) EXPECT_EQ(untouched[entry], 0.0f);
}

TEST_P(Proprioception, FixedProtocolZeroesOnlyTheNeckEntries) {
  ProprioceptionBatch head(env_.model().robot, 2);
  ProprioceptionBatch fixed(env_.model().robot, 2);
  fixed.SetCameraProtocol(CameraProtocol::kFixed);
  head.Update(env_.state(), {1, 1});
  fixed.Update(env_.state(), {1, 1});
  for (int entry = 0; entry < head.state_size(); ++entry) {
    const bool neck =
        entry == fixed.neck_entries()[0] || entry == fixed.neck_entries()[1] || entry == fixed.neck_entries()[2];
    EXPECT_EQ(fixed.state(0)[entry], neck ? 0.0f : head.state(0)[entry]) << "entry " << entry;
  }
}

TEST_P(Proprioception, EndEffectorPosesAreTheIkLinksInTheCanonicalAndWorldFrames) {
  ProprioceptionBatch proprioception(env_.model().robot, 2);
  proprioception.Update(env_.state(), {1, 1});
  std::vector<RigidTransform> X_BL(robot_.links.size());
  kinematics::ComputeLinkPoses(robot_, env_.state().q_row(0), X_BL.data());
  for (const kinematics::Side side : kinematics::kSides) {
    const RigidTransform& X_BE = X_BL[static_cast<std::size_t>(robot_.arm(side).ik_link)];
    const Vec3 expected = robot_.BaseToCanonical(X_BE.translation());
    const float* p = proprioception.eef_position(0, side);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(p[k], expected[k], 1e-6);
    const float* q = proprioception.eef_quaternion(0, side);
    const Quat rotation(q[0], q[1], q[2], q[3]);
    EXPECT_NEAR(rotation.norm(), 1.0, 1e-6);
    EXPECT_LT(Quat(X_BE.linear()).angularDistance(rotation.cast<double>()), 1e-5);
  }
}

INSTANTIATE_TEST_SUITE_P(BothRobots, Proprioception, ::testing::Values("gr1t2", "reachy2"));

}  // namespace
}  // namespace tavis::batch

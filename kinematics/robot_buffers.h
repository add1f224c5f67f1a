// Fixed-size buffers for one robot configuration, for per-tick paths (the step, the experts):
// these run at every control tick of every env and allocate nothing. The VecEnv rejects a robot
// that does not fit them when it is built.
#pragma once

#include <array>

#include "kinematics/invariant.h"
#include "kinematics/pose.h"
#include "kinematics/robot_model.h"

namespace tavis {

constexpr int kMaxRobotLinks = 64;
constexpr int kMaxRobotJoints = 64;

using LinkPoses = std::array<RigidTransform, kMaxRobotLinks>;  // X_BL, indexed by link
using JointPositions = std::array<double, kMaxRobotJoints>;    // q, indexed by joint
using ArmJoints = std::array<double, kinematics::kArmDof>;     // one arm's joints, in ArmSpec order

// One arm's joints out of a full joint vector q.
inline ArmJoints ArmOf(const kinematics::RobotModel& robot, kinematics::Side side, const double* q) {
  ArmJoints joints{};
  for (int k = 0; k < kinematics::kArmDof; ++k) joints[k] = q[robot.arm(side).joints[k]];
  return joints;
}

inline void CheckFitsRobotBuffers(const kinematics::RobotModel& robot) {
  TAVIS_INVARIANT(robot.num_links() <= kMaxRobotLinks, "robot links fit a LinkPoses buffer");
  TAVIS_INVARIANT(robot.num_joints() <= kMaxRobotJoints, "robot joints fit a JointPositions buffer");
}

}  // namespace tavis

// Link poses for kinematics tests; the robots load through tests/support/robot_loading.h.
#pragma once

#include <vector>

#include "kinematics/forward_kinematics.h"
#include "tests/support/robot_loading.h"

namespace tavis::kinematics::testing {

inline std::vector<RigidTransform> LinkPoses(const kinematics::RobotModel& robot, const std::vector<double>& q) {
  std::vector<RigidTransform> X_BL(robot.links.size());
  kinematics::ComputeLinkPoses(robot, q.data(), X_BL.data());
  return X_BL;
}

}  // namespace tavis::kinematics::testing

// Loads the project's robot configs for kinematics tests.
#pragma once

#include <string>
#include <vector>

#include "configs/robot_config.h"
#include "kinematics/forward_kinematics.h"

namespace tavis::testing {

inline kinematics::RobotModel LoadRobot(const std::string& name) {
  return configs::LoadRobotModel(configs::RobotConfigPath(TAVIS_CONFIG_DIR, name));
}

inline std::vector<RigidTransform> LinkPoses(const kinematics::RobotModel& robot, const std::vector<double>& q) {
  std::vector<RigidTransform> X_BL(robot.links.size());
  kinematics::ComputeLinkPoses(robot, q.data(), X_BL.data());
  return X_BL;
}

}  // namespace tavis::testing

// The project's robots as every test suite loads them: configs/robots/<name>.yaml through the
// real loader. Suites define TAVIS_CONFIG_DIR (tests/CMakeLists.txt, tavis_add_test_suite).
#pragma once

#include <string>

#include "configs/robot_config.h"
#include "kinematics/robot_model.h"

namespace tavis::testing {

// The robot `name` ("gr1t2", "reachy2") from the repository's configs/robots/.
inline kinematics::RobotModel LoadRobot(const std::string& name) {
  return configs::LoadRobotModel(configs::RobotConfigPath(TAVIS_CONFIG_DIR, name));
}

}  // namespace tavis::testing

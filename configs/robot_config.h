// Loads configs/robots/<name>.yaml into a kinematics::RobotModel.
#pragma once

#include <string>
#include <vector>

#include "kinematics/robot_model.h"

namespace tavis::configs {

// Throws ConfigError naming the file and key path for a missing, unknown or invalid entry.
kinematics::RobotModel LoadRobotModel(const std::string& path);

// The robot file for a robot name inside a config directory: <dir>/robots/<name>.yaml. Throws
// ConfigError listing the known robots if there is no such file.
std::string RobotConfigPath(const std::string& config_dir, const std::string& robot_name);

// The robots of a config directory: the names of <dir>/robots/*.yaml, sorted.
std::vector<std::string> KnownRobots(const std::string& config_dir);

}  // namespace tavis::configs

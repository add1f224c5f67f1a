// Loads configs/robots/<name>.yaml into a kinematics::RobotModel.
//
// The loader validates a robot completely, so that nothing it accepts can crash the physics
// (ODE aborts on a zero mass, size or axis) or the renderer. Every number is range-checked:
//   link and finger masses       [0.05, 1000] kg (0.05 kg: kinematics::kMinBodyMass)
//   box sizes, radii, heights,
//   pad and housing sizes         (0, 10] m; a capsule's ends a != b
//   positions (xyz, centres, tcp,
//   capsule ends, offsets)        [-10, 10] m
//   angles (rpy, joint limits,
//   unsimulated state values)     [-2 pi, 2 pi] rad; joint lower < upper, default within them
//   joint axes, closing axis      unit vectors (norm within 1e-3 of 1; then normalised exactly),
//                                 the closing axis along x, y or z (the pads are axis-aligned)
//   velocity limit                (0, 100] rad/s     effort limit (0, 10000] N m
//   position gain                 (0, 10000] 1/s
//   ik damping                    (0, 10]            nullspace gain [0, 100]
//   gripper gaps                  open_gap in (0, 10] m above closed_gap in [0, 10] m
//   finger force                  (0, 10000] N       finger speed (0, 10] m/s
//   camera focal length           (0, 1000] mm       near (0, 1000] m, far in (near, 1000] m
// and the structure is checked: joint, link and camera names unique; the two arms and the neck
// on disjoint joints and every joint in one of them; each arm's ik_link moved by exactly that
// arm's joints (so not base_link); the gripper's pads hang below its housing. Camera resolution
// and aperture are not part of a robot file (render::CameraSpec takes them from the protocol).
#pragma once

#include <string>
#include <vector>

#include "kinematics/robot_model.h"

namespace tavis::configs {

// Throws ConfigError "file: key.path: message" naming the file, the key path and the bad value
// for a missing, unknown, duplicate or invalid entry.
kinematics::RobotModel LoadRobotModel(const std::string& path);
// The same from the file's text, read by a caller that also records it (YamlValue::ReadFileText;
// a cell's plan): `path` names the file in errors, and its name must be the robot's.
kinematics::RobotModel ParseRobotModel(const std::string& text, const std::string& path);

// The robot file for a robot name inside a config directory: <dir>/robots/<name>.yaml. Throws
// ConfigError listing the known robots if there is no such file.
std::string RobotConfigPath(const std::string& config_dir, const std::string& robot_name);

// The robots of a config directory: the names of <dir>/robots/*.yaml, sorted.
std::vector<std::string> KnownRobots(const std::string& config_dir);

}  // namespace tavis::configs

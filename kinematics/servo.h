// The servo law every actuator of the simulation follows, simulated or kinematic: a velocity
// target proportional to the position error, bounded by the actuator's speed limit. The arm
// joints (engine/physics_world.cc, engine/internal/kinematic_arms.cc), the fingers' sliders
// (the same files), the expert's neck command (scenarios/pick_expert.cc) and the MuJoCo peer
// benchmark (bench/peer) all servo with it.
#pragma once

#include <algorithm>

#include "kinematics/robot_model.h"

namespace tavis::kinematics {

// Finger servo: the slider's velocity target per metre of closing-position error, bounded by
// the gripper's speed limit (GripperSpec::max_speed).
constexpr double kFingerServoGain = 40.0;  // 1/s

// gain * error, clamped to [-speed_limit, speed_limit].
inline double ServoVelocity(double gain, double error, double speed_limit) {
  return std::clamp(gain * error, -speed_limit, speed_limit);
}

// An arm joint's servo velocity (rad/s) toward a target `error` rad away.
inline double JointServoVelocity(const ActuatorLimits& actuator, double error) {
  return ServoVelocity(actuator.position_gain, error, actuator.velocity_limit);
}

}  // namespace tavis::kinematics

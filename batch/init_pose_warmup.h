// The ood-init-pose split (reference 7.3): every episode starts with a warm-up in which one
// perturbed action is held for ten 20 Hz steps: both hand targets at the teleop rest pose with
// Gaussian position noise (0.10 m per axis), neck pitch and yaw with Gaussian noise (0.175 rad),
// grippers open. The warm-up's steps count toward the episode.
#pragma once

#include "engine/random.h"
#include "kinematics/action.h"
#include "kinematics/robot_model.h"

namespace tavis::batch {

constexpr int kInitPoseWarmupPolicySteps = 10;   // max(5, int(0.5 * 20 Hz))
constexpr double kInitPosePositionNoise = 0.10;  // m
constexpr double kInitPoseNeckNoise = 0.175;     // rad

// Draws the warm-up action in the reference's order: left position noise (x, y, z), right
// position noise, neck pitch, neck yaw. No clipping.
kinematics::Action InitPoseWarmupAction(const kinematics::RobotModel& robot, engine::RandomStream& rng);

}  // namespace tavis::batch

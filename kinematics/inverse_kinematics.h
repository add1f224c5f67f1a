// Damped-least-squares differential IK with a null-space pull to the default arm pose, one
// step per call over the arm's 7 joints (reference section 7.1). Called once per control tick
// from the measured joint positions, as the reference does every physics step.
#pragma once

#include <array>

#include "kinematics/forward_kinematics.h"

namespace tavis::kinematics {

struct PoseTarget {
  Vec3 position = Vec3::Zero();         // base frame
  Quat orientation = Quat::Identity();  // base frame, (w, x, y, z); not normalised, as in IsaacLab
};

// Joint position targets for the arm after one DLS step from q toward `target`, given link
// poses X_BL computed for the same q. The result respects the joint limits (joints that would
// cross one are pinned at it and the step re-solved), unlike the reference (docs/fidelity.md).
std::array<double, kArmDof> IkStep(const RobotModel& robot, Side side, const double* q, const RigidTransform* X_BL,
                                   const PoseTarget& target);

// Pose error (position, axis-angle rotation) of the arm's IK link with respect to `target`.
Vec6 IkPoseError(const RobotModel& robot, Side side, const RigidTransform* X_BL, const PoseTarget& target);

}  // namespace tavis::kinematics

// How far an arm's hand can be from its shoulder, whatever its joints: the planner's proof that
// no IK seed can reach a target, so that it need not iterate any (arm_planner.h).
#pragma once

#include "kinematics/robot_model.h"

namespace tavis::scenarios::expert {

// The arm's reach sphere: the origin of its topmost moving link, which no arm joint moves (a
// link's joint turns the link about its own origin), and an upper bound on the IK link origin's
// distance from it in any configuration: the sum of the lengths of the fixed offsets of the links
// below it down to the IK link (triangle inequality).
struct ArmReach {
  Vec3 centre = Vec3::Zero();  // base frame
  double radius = 0.0;         // m
};

// X_BL: the link poses of any configuration (kinematics::ComputeLinkPoses); only links the arm
// does not move are read.
ArmReach ArmReachOf(const kinematics::RobotModel& robot, kinematics::Side side, const RigidTransform* X_BL);

}  // namespace tavis::scenarios::expert

#include "scenarios/expert/arm_reach.h"

#include "kinematics/invariant.h"

namespace tavis::scenarios::expert {

ArmReach ArmReachOf(const kinematics::RobotModel& robot, kinematics::Side side, const RigidTransform* X_BL) {
  // The topmost moving link of the IK link's chain: every joint on the chain is one of this arm's
  // (configs::LoadRobotModel checks it), so no arm joint moves this link's origin.
  int shoulder = kinematics::kBaseLink;
  for (int link = robot.arm(side).ik_link; link != kinematics::kBaseLink;
       link = robot.links[static_cast<std::size_t>(link)].parent) {
    if (robot.links[static_cast<std::size_t>(link)].joint >= 0) shoulder = link;
  }
  TAVIS_INVARIANT(shoulder != kinematics::kBaseLink, "the ik_link is moved by the arm's joints");
  ArmReach reach;
  reach.centre = X_BL[static_cast<std::size_t>(shoulder)].translation();
  for (int link = robot.arm(side).ik_link; link != shoulder;
       link = robot.links[static_cast<std::size_t>(link)].parent) {
    reach.radius += robot.links[static_cast<std::size_t>(link)].origin.translation().norm();
  }
  return reach;
}

}  // namespace tavis::scenarios::expert

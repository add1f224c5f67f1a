#include "kinematics/forward_kinematics.h"

#include <algorithm>
#include <cstdint>

namespace tavis::kinematics {

namespace {

void ComputeLinkPose(const RobotModel& robot, const double* q, int i, RigidTransform* X_BL) {
  const Link& link = robot.links[i];
  RigidTransform X_PL = link.origin;
  if (link.joint >= 0) {
    const Joint& joint = robot.joints[link.joint];
    X_PL.linear() = X_PL.linear() * Eigen::AngleAxisd(q[link.joint], joint.axis).toRotationMatrix();
  }
  X_BL[i] = link.parent < 0 ? X_PL : X_BL[link.parent] * X_PL;
}

}  // namespace

void ComputeLinkPoses(const RobotModel& robot, const double* q, RigidTransform* X_BL) {
  for (int i = 0; i < robot.num_links(); ++i) ComputeLinkPose(robot, q, i, X_BL);
}

void ComputeLinkPosesOf(const RobotModel& robot, const double* q, const std::vector<int>& links, RigidTransform* X_BL) {
  for (int i : links) ComputeLinkPose(robot, q, i, X_BL);
}

void ComputeLinkPoseChain(const RobotModel& robot, const double* q, int link, RigidTransform* X_BL) {
  const int parent = robot.links[link].parent;
  if (parent >= 0) ComputeLinkPoseChain(robot, q, parent, X_BL);
  ComputeLinkPose(robot, q, link, X_BL);
}

Vec3 ToolCentrePointWorld(const RobotModel& robot, const double* q, Side side, RigidTransform* X_BL) {
  const int link = robot.arm(side).ik_link;
  ComputeLinkPoseChain(robot, q, link, X_BL);
  return robot.root_world + X_BL[link] * robot.gripper.tcp;
}

std::vector<int> LinksMovedByArm(const RobotModel& robot, Side side) {
  const ArmSpec& arm = robot.arm(side);
  std::vector<uint8_t> moved(static_cast<std::size_t>(robot.num_links()), 0);
  std::vector<int> links;
  for (int i = 0; i < robot.num_links(); ++i) {
    const Link& link = robot.links[i];
    const bool own_joint =
        link.joint >= 0 && std::find(arm.joints.begin(), arm.joints.end(), link.joint) != arm.joints.end();
    moved[i] = own_joint || (link.parent >= 0 && moved[link.parent]);
    if (moved[i]) links.push_back(i);
  }
  return links;
}

ArmJacobian ComputeArmJacobian(const RobotModel& robot, Side side, const RigidTransform* X_BL) {
  const ArmSpec& arm = robot.arm(side);
  const Vec3 p_end = X_BL[arm.ik_link].translation();
  ArmJacobian J;
  for (int column = 0; column < kArmDof; ++column) {
    const Joint& joint = robot.joints[arm.joints[column]];
    const RigidTransform& X_BJ = X_BL[joint.link];  // the axis is fixed in the child frame
    const Vec3 axis = X_BJ.linear() * joint.axis;
    J.block<3, 1>(0, column) = axis.cross(p_end - X_BJ.translation());
    J.block<3, 1>(3, column) = axis;
  }
  return J;
}

}  // namespace tavis::kinematics

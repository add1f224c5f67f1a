// Forward kinematics and Jacobians of a RobotModel, one robot configuration at a time; the
// batch stages call these per env inside their parallel loops.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "kinematics/robot_model.h"

namespace tavis::kinematics {

using ArmJacobian = Eigen::Matrix<double, 6, kArmDof>;  // rows: linear (3), angular (3)

// Pose of every link in the base frame, X_BL[link], for joint positions q (num_joints).
void ComputeLinkPoses(const RobotModel& robot, const double* q, RigidTransform* X_BL);
// The same for `links` only (ascending; each link's parent is in `links` or already in X_BL):
// one arm's chain when nothing else moved.
void ComputeLinkPosesOf(const RobotModel& robot, const double* q, const std::vector<int>& links, RigidTransform* X_BL);
// The pose of `link` and of its ancestors only (what a camera or hand pose needs); allocates
// nothing.
void ComputeLinkPoseChain(const RobotModel& robot, const double* q, int link, RigidTransform* X_BL);
// The links whose pose depends on the arm's joints, ascending: what ComputeLinkPosesOf needs
// after only that arm's joints changed.
std::vector<int> LinksMovedByArm(const RobotModel& robot, Side side);

// World position of `side`'s tool centre point (GripperSpec::tcp, between the pads) at joint
// positions q; X_BL is scratch for the arm's chain of link poses (num_links entries).
Vec3 ToolCentrePointWorld(const RobotModel& robot, const double* q, Side side, RigidTransform* X_BL);

// Geometric Jacobian of the arm's IK link origin in the base frame, from link poses already
// computed by ComputeLinkPoses for the same q.
ArmJacobian ComputeArmJacobian(const RobotModel& robot, Side side, const RigidTransform* X_BL);

// Pose of a camera (IsaacLab "world" convention) in the base frame.
inline RigidTransform CameraPose(const RobotModel& robot, int camera, const RigidTransform* X_BL) {
  const CameraMount& mount = robot.cameras[camera];
  return X_BL[mount.link] * mount.X_LC;
}

}  // namespace tavis::kinematics

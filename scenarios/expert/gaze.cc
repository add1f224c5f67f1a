#include "scenarios/expert/gaze.h"

#include <algorithm>
#include <cmath>

#include "kinematics/forward_kinematics.h"
#include "kinematics/robot_buffers.h"

namespace tavis::scenarios::expert {
namespace {

// Direction to the target in the head camera frame (x forward, y left, z up).
Vec3 TargetInCamera(const kinematics::RobotModel& robot, const double* q, const Vec3& target_world) {
  const int camera = robot.CameraIndex("head");
  LinkPoses X_BL;
  kinematics::ComputeLinkPoseChain(robot, q, robot.cameras[camera].link, X_BL.data());
  const RigidTransform X_BC = kinematics::CameraPose(robot, camera, X_BL.data());
  return X_BC.inverse() * (target_world - robot.root_world);
}

// Horizontal and vertical angular offsets of the target from the optical axis.
Eigen::Vector2d AngularOffsets(const Vec3& t) {
  return Eigen::Vector2d(std::atan2(t.y(), t.x()), std::atan2(t.z(), std::hypot(t.x(), t.y())));
}

}  // namespace

std::array<double, 3> FixationNeckAngles(const kinematics::RobotModel& robot, const double* q_in,
                                         const Vec3& target_world, NeckLimits limits) {
  CheckFitsRobotBuffers(robot);
  JointPositions q{};
  std::copy(q_in, q_in + robot.num_joints(), q.begin());
  const int roll = robot.neck_joints[0];
  const int pitch = robot.neck_joints[1];
  const int yaw = robot.neck_joints[2];
  q[roll] = 0.0;
  auto clamp_to_limits = [&](int joint) {
    if (limits == NeckLimits::kIgnore) return;
    q[joint] = std::clamp(q[joint], robot.joints[joint].lower, robot.joints[joint].upper);
  };
  // Gauss-Newton on (yaw, pitch) with a finite-difference Jacobian: the head chain is short and
  // the camera's mount offset makes a closed form awkward.
  for (int iteration = 0; iteration < 12; ++iteration) {
    const Eigen::Vector2d offsets = AngularOffsets(TargetInCamera(robot, q.data(), target_world));
    if (offsets.norm() < 1e-5) break;
    Eigen::Matrix2d J;
    const double h = 1e-5;
    const int joints[2] = {yaw, pitch};
    for (int c = 0; c < 2; ++c) {
      JointPositions q_h = q;
      q_h[joints[c]] += h;
      J.col(c) = (AngularOffsets(TargetInCamera(robot, q_h.data(), target_world)) - offsets) / h;
    }
    const Eigen::Vector2d step = J.colPivHouseholderQr().solve(-offsets);
    q[yaw] += step[0];
    q[pitch] += step[1];
    clamp_to_limits(yaw);
    clamp_to_limits(pitch);
  }
  return {0.0, q[pitch], q[yaw]};
}

double GazeError(const kinematics::RobotModel& robot, const double* q, const Vec3& target_world) {
  CheckFitsRobotBuffers(robot);
  const Vec3 t = TargetInCamera(robot, q, target_world);
  return std::acos(std::clamp(t.normalized().x(), -1.0, 1.0));
}

double ClosestGazeError(const kinematics::RobotModel& robot, const double* q, const Vec3& target_world) {
  CheckFitsRobotBuffers(robot);
  JointPositions aimed{};
  std::copy(q, q + robot.num_joints(), aimed.begin());
  const std::array<double, 3> neck = FixationNeckAngles(robot, q, target_world);
  for (int k = 0; k < 3; ++k)
    aimed[static_cast<std::size_t>(robot.neck_joints[static_cast<std::size_t>(k)])] = neck[static_cast<std::size_t>(k)];
  return GazeError(robot, aimed.data(), target_world);
}

}  // namespace tavis::scenarios::expert

#include "scenarios/expert/hand_motion.h"

#include <algorithm>
#include <cmath>

#include "scenarios/expert/arm_planner.h"

namespace tavis::scenarios::expert {

using kinematics::Side;

void HandMotion::Reset(const kinematics::RobotModel& robot, const double* q) {
  CheckFitsRobotBuffers(robot);
  std::copy(q, q + robot.num_joints(), q_.begin());
  for (Side side : kinematics::kSides) command_[kinematics::Index(side)] = HandPoseCanonical(robot, side, q);
  segments_ = {};
}

RigidTransform HandMotion::PoseAt(const kinematics::RobotModel& robot, Side side, const ArmJoints& joints) {
  const auto& arm_joints = robot.arm(side).joints;
  for (int k = 0; k < kinematics::kArmDof; ++k) q_[arm_joints[k]] = joints[k];
  return HandPoseCanonical(robot, side, q_.data());
}

void HandMotion::StartSegment(const engine::WorldModel& model, Side side, const ArmJoints& from, const ArmJoints& to,
                              double joint_speed, double hand_speed) {
  double joint_distance = 0.0;
  for (int k = 0; k < kinematics::kArmDof; ++k) joint_distance = std::max(joint_distance, std::abs(to[k] - from[k]));
  const Vec3 start = PoseAt(model.robot, side, from).translation();
  const Vec3 end = PoseAt(model.robot, side, to).translation();
  const double duration = std::max({joint_distance / joint_speed, (end - start).norm() / hand_speed, 0.1});
  segments_[kinematics::Index(side)] = {from, to, 0.0, 1.0 / (duration * model.physics.control_hz)};
}

bool HandMotion::FollowSegment(const kinematics::RobotModel& robot, Side side) {
  Segment& s = segments_[kinematics::Index(side)];
  s.progress = std::min(1.0, s.progress + s.rate);
  // Smoothstep timing: the hand starts and stops gently.
  const double blend = s.progress * s.progress * (3.0 - 2.0 * s.progress);
  ArmJoints joints;
  for (int k = 0; k < kinematics::kArmDof; ++k) joints[k] = s.from[k] + blend * (s.to[k] - s.from[k]);
  command_[kinematics::Index(side)] = PoseAt(robot, side, joints);
  return s.progress >= 1.0;
}

bool HandMotion::MoveToward(const engine::WorldModel& model, Side side, const ArmJoints& goal, double speed) {
  const RigidTransform target = PoseAt(model.robot, side, goal);
  RigidTransform& hand = command_[kinematics::Index(side)];
  const Vec3 delta = target.translation() - hand.translation();
  const double max_step = speed / model.physics.control_hz;
  const double distance = delta.norm();
  // The same fraction of the remaining translation and rotation: a straight line with the
  // orientation turning in proportion.
  const double fraction = distance > max_step ? max_step / distance : 1.0;
  hand.translation() += fraction * delta;
  // Normalised at every step: repeated matrix-quaternion round trips otherwise drift off the
  // rotation group, and the drift grows until the commanded hand turns away from its target.
  hand.linear() = Quat(hand.linear())
                      .normalized()
                      .slerp(fraction, Quat(target.linear()).normalized())
                      .normalized()
                      .toRotationMatrix();
  return fraction >= 1.0;
}

}  // namespace tavis::scenarios::expert

#include "scenarios/pick_expert.h"

#include <algorithm>
#include <cmath>

#include "kinematics/forward_kinematics.h"
#include "scenarios/gaze.h"

namespace tavis::scenarios {
namespace {

using kinematics::Side;

// Moves `current` toward `goal` by at most max_step metres and max_turn radians; returns true
// once it is there.
bool MoveToward(RigidTransform& current, const RigidTransform& goal, double max_step, double max_turn) {
  const Vec3 delta = goal.translation() - current.translation();
  const double distance = delta.norm();
  current.translation() += distance > max_step ? delta * (max_step / distance) : delta;
  const Quat from(current.linear());
  const Quat to(goal.linear());
  const double angle = from.angularDistance(to);
  current.linear() = (angle > max_turn ? from.slerp(max_turn / angle, to) : to).toRotationMatrix();
  return distance <= max_step && angle <= max_turn;
}

void WriteArm(kinematics::Action& action, Side side, const RigidTransform& X_CanonicalHand) {
  const int p = kinematics::action::kArmPosition[kinematics::Index(side)];
  const int r = kinematics::action::kArmQuaternion[kinematics::Index(side)];
  const Quat q(X_CanonicalHand.linear());
  for (int k = 0; k < 3; ++k) action[p + k] = X_CanonicalHand.translation()[k];
  action[r] = q.w();
  action[r + 1] = q.x();
  action[r + 2] = q.y();
  action[r + 3] = q.z();
}

// Yaw of a z-up object's x axis, folded into [-pi/4, pi/4]: a parallel gripper can take a box
// by either pair of faces.
double FoldedYaw(const Quat& orientation) {
  const Vec3 x_axis = orientation * Vec3::UnitX();
  const double yaw = std::atan2(x_axis.y(), x_axis.x());
  const double quarter = M_PI / 2.0;
  return yaw - quarter * std::round(yaw / quarter);
}

}  // namespace

PickExpertSettings PickSettingsFor(const kinematics::RobotModel& robot) {
  PickExpertSettings settings;
  settings.grasp_tilt = robot.name == "reachy2" ? 0.6 : 0.35;
  return settings;
}

PickExpert::PickExpert(const engine::WorldModel&, int num_envs, PickExpertSettings settings)
    : settings_(settings), memory_(num_envs) {}

void PickExpert::Enter(EnvMemory& m, Phase phase, int step) const {
  m.phase = phase;
  m.phase_start_step = step;
}

void PickExpert::Reset(const engine::WorldModel& model, const engine::BatchState& state, int env) {
  const kinematics::RobotModel& robot = model.robot;
  EnvMemory& m = memory_[env];
  m = EnvMemory();
  std::vector<RigidTransform> X_BL(robot.links.size());
  kinematics::ComputeLinkPoses(robot, state.q_row(env), X_BL.data());
  for (Side side : kinematics::kSides) {
    RigidTransform X = X_BL[robot.arm(side).ik_link];
    X.translation() = robot.BaseToCanonical(X.translation());
    m.hand_command[kinematics::Index(side)] = X;
  }
  for (int i = 0; i < kinematics::kNeckDof; ++i) m.neck_command[i] = state.q_row(env)[robot.neck_joints[i]];
  m.neck_goal = m.neck_command;
  m.fixated_point = Vec3::Constant(1e9);
}

RigidTransform PickExpert::GraspPose(const engine::WorldModel& model, const engine::BatchState& state, int env,
                                     double height_above) const {
  const kinematics::RobotModel& robot = model.robot;
  const int target = static_cast<int>(state.task_vars_row(env)[settings_.target_task_var]);
  const Vec3 p_object = state.ObjectPosition(env, target);
  const Mat3 R = (Eigen::AngleAxisd(FoldedYaw(state.ObjectOrientation(env, target)), Vec3::UnitZ()) *
                  Eigen::AngleAxisd(-settings_.grasp_tilt, Vec3::UnitY()))
                     .toRotationMatrix();
  const Vec3 tcp_world = p_object + Vec3(0.0, 0.0, settings_.grasp_height + height_above);
  const Vec3 hand_base = tcp_world - robot.root_world - R * robot.gripper.tcp;
  return MakeTransform(robot.BaseToCanonical(hand_base), R);
}

void PickExpert::UpdateNeck(const engine::WorldModel& model, const engine::BatchState& state, int env,
                            EnvMemory& m) const {
  const int target = static_cast<int>(state.task_vars_row(env)[settings_.target_task_var]);
  const Vec3 p_object = state.ObjectPosition(env, target);
  // Re-aim only when the object has moved noticeably: the solve is the expert's costliest step.
  if ((p_object - m.fixated_point).norm() > 0.01) {
    m.neck_goal = FixationNeckAngles(model.robot, state.q_row(env), p_object);
    m.fixated_point = p_object;
  }
  const double dt = 1.0 / model.physics.control_hz;
  for (int i = 0; i < kinematics::kNeckDof; ++i) {
    const double rate = std::clamp(settings_.neck_gain * (m.neck_goal[i] - m.neck_command[i]),
                                   -settings_.neck_max_speed, settings_.neck_max_speed);
    m.neck_command[i] += rate * dt;
  }
}

void PickExpert::Act(const engine::WorldModel& model, const engine::BatchState& state, int env,
                     kinematics::Action& action) {
  EnvMemory& m = memory_[env];
  const int step = state.control_step[env];
  const double dt = 1.0 / model.physics.control_hz;
  const double elapsed = (step - m.phase_start_step) * dt;
  UpdateNeck(model, state, env, m);
  RigidTransform& hand = m.hand_command[kinematics::Index(m.side)];

  switch (m.phase) {
    case Phase::kLook: {
      double neck_error = 0.0;
      for (int i = 0; i < kinematics::kNeckDof; ++i) neck_error = std::max(neck_error, std::abs(m.neck_goal[i] - m.neck_command[i]));
      if (neck_error < 0.01) Enter(m, Phase::kSettle, step);
      break;
    }
    case Phase::kSettle:
      if (elapsed >= settings_.settle_s) {
        const int target = static_cast<int>(state.task_vars_row(env)[settings_.target_task_var]);
        m.side = state.ObjectPosition(env, target).y() >= 0.0 ? kinematics::Side::kLeft : kinematics::Side::kRight;
        Enter(m, Phase::kApproach, step);
      }
      break;
    case Phase::kApproach:
      if (MoveToward(hand, GraspPose(model, state, env, settings_.approach_height), settings_.hand_speed * dt,
                     settings_.hand_turn_speed * dt)) {
        Enter(m, Phase::kDescend, step);
      }
      break;
    case Phase::kDescend:
      if (MoveToward(hand, GraspPose(model, state, env, 0.0), settings_.descend_speed * dt,
                     settings_.hand_turn_speed * dt)) {
        Enter(m, Phase::kClose, step);
      }
      break;
    case Phase::kClose:
      m.gripper_command[kinematics::Index(m.side)] = 1.0;
      if (elapsed >= settings_.close_s) Enter(m, Phase::kLift, step);
      break;
    case Phase::kLift: {
      RigidTransform lifted = hand;
      lifted.translation().z() = settings_.lift_to_z - model.robot.root_world.z() - model.robot.canonical_offset.z() -
                                 (hand.linear() * model.robot.gripper.tcp).z();
      MoveToward(hand, lifted, settings_.descend_speed * dt, settings_.hand_turn_speed * dt);
      break;
    }
  }

  for (Side side : kinematics::kSides) WriteArm(action, side, m.hand_command[kinematics::Index(side)]);
  action[kinematics::action::kNeckRoll] = m.neck_command[0];
  action[kinematics::action::kNeckPitch] = m.neck_command[1];
  action[kinematics::action::kNeckYaw] = m.neck_command[2];
  for (Side side : kinematics::kSides) {
    action[kinematics::action::kGripper[kinematics::Index(side)]] = m.gripper_command[kinematics::Index(side)];
  }
}

}  // namespace tavis::scenarios

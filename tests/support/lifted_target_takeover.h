// An alteration for AlteredExpertPolicy (altered_expert_policy.h): the scripted expert reaches,
// grasps and lifts the target as it does; once a hand it closed holds the target `lift_m` above
// where it stood, that hand follows a script instead (the other hand and the neck keep the
// expert's commands). Each tick the script says where the hand's tool centre point goes, as a
// world pose, and whether the hand opens; once it has opened it stays open. So a test policy can
// do with a target held in the expert's own grasp what no hand sent from its start pose reaches.
// Uses the alteration's memory byte: 0 while the expert acts, 1 once taken over.
#pragma once

#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "batch/policy.h"
#include "kinematics/action.h"
#include "kinematics/pose.h"

namespace tavis::testing {

class LiftedTargetTakeover {
 public:
  // An env's takeover: the hand holding the target, the control tick and its commanded tool
  // centre point (world) then, and the same when the script first opened it (tick -1: not yet).
  struct Takeover {
    int hand = -1;
    int tick = -1;
    RigidTransform X_W_tcp = RigidTransform::Identity();
    int release_tick = -1;
    RigidTransform X_W_release = RigidTransform::Identity();
  };
  struct HandCommand {
    RigidTransform X_W_tcp = RigidTransform::Identity();
    bool open = false;
  };
  using Script = std::function<HandCommand(const batch::Observation& observation, int env, const Takeover& takeover)>;

  LiftedTargetTakeover(int num_envs, double lift_m, Script script)
      : lift_m_(lift_m),
        script_(std::move(script)),
        rest_z_(static_cast<std::size_t>(num_envs), 0.0),
        takeovers_(static_cast<std::size_t>(num_envs)) {}

  // The env's takeover this episode (hand -1: the expert has not lifted the target yet).
  const Takeover& takeover(int env) const { return takeovers_[static_cast<std::size_t>(env)]; }

  void operator()(const batch::Observation& observation, int env, kinematics::Action& action, uint8_t& memory) {
    const engine::BatchState& state = observation.state;
    const kinematics::RobotModel& robot = observation.model.robot;
    const double target_z = state.ObjectPosition(env, state.target(env)).z();
    Takeover& takeover = takeovers_[static_cast<std::size_t>(env)];
    if (memory == 0) {
      takeover = Takeover{};
      int closing = -1;
      for (int hand = 0; hand < 2; ++hand) {
        if (action[kinematics::action::kGripper[hand]] > 0.0) closing = hand;
      }
      // Where the target stood: its height until a hand closes on it.
      if (closing < 0) rest_z_[static_cast<std::size_t>(env)] = target_z;
      if (closing < 0 || target_z - rest_z_[static_cast<std::size_t>(env)] < lift_m_) return;
      memory = 1;
      takeover.hand = closing;
      takeover.tick = state.control_step[env];
      takeover.X_W_tcp = CommandedTcp(robot, action, closing);
    }
    const HandCommand command = script_(observation, env, takeover);
    if (command.open && takeover.release_tick < 0) {
      takeover.release_tick = state.control_step[env];
      takeover.X_W_release = command.X_W_tcp;
    }
    WriteTcp(robot, command.X_W_tcp, takeover.hand, action);
    action[kinematics::action::kGripper[takeover.hand]] = takeover.release_tick >= 0 ? -1.0 : 1.0;
  }

 private:
  // The action's IK target is the IK link's origin in the canonical frame and its orientation;
  // the tool centre point hangs from it at robot.gripper.tcp.
  static RigidTransform CommandedTcp(const kinematics::RobotModel& robot, const kinematics::Action& action, int hand) {
    const int p = kinematics::action::kArmPosition[hand];
    const int r = kinematics::action::kArmQuaternion[hand];
    const Mat3 R = Quat(action[r], action[r + 1], action[r + 2], action[r + 3]).normalized().toRotationMatrix();
    const Vec3 ik = robot.root_world + robot.CanonicalToBase(Vec3(action[p], action[p + 1], action[p + 2]));
    return MakeTransform(ik + R * robot.gripper.tcp, R);
  }
  static void WriteTcp(const kinematics::RobotModel& robot, const RigidTransform& X_W_tcp, int hand,
                       kinematics::Action& action) {
    const Vec3 ik =
        robot.BaseToCanonical(X_W_tcp.translation() - X_W_tcp.linear() * robot.gripper.tcp - robot.root_world);
    const Quat q(X_W_tcp.linear());
    const int p = kinematics::action::kArmPosition[hand];
    const int r = kinematics::action::kArmQuaternion[hand];
    for (int k = 0; k < 3; ++k) action[p + k] = ik[k];
    action[r] = q.w();
    action[r + 1] = q.x();
    action[r + 2] = q.y();
    action[r + 3] = q.z();
  }

  double lift_m_;
  Script script_;
  std::vector<double> rest_z_;  // per env: the target's height before a hand closed on it
  std::vector<Takeover> takeovers_;
};

}  // namespace tavis::testing

// A privileged scripted expert that picks one object and lifts it, looking before it reaches
// (the human teleoperator's timing that GALT measures): it turns the head to fixate the object,
// lets the neck settle, then moves the nearer arm above the object, descends, closes and lifts.
// Motions are smooth and speed-limited at the control rate.
#pragma once

#include <array>
#include <vector>

#include "scenarios/scenario.h"

namespace tavis::scenarios {

struct PickExpertSettings {
  int target_task_var = 0;           // task variable holding the target object's index
  double grasp_tilt = 0.0;           // rad: approach tilted forward from vertical
  double grasp_height = 0.0;         // m: TCP above the object's centre at the grasp
  double approach_height = 0.10;     // m: pre-grasp above the grasp
  double lift_to_z = 1.26;           // m: world height of the TCP after lifting (success: 1.2)
  double hand_speed = 0.30;          // m/s
  double descend_speed = 0.15;       // m/s
  double hand_turn_speed = 1.5;      // rad/s
  double neck_gain = 5.0;            // 1/s
  double neck_max_speed = 1.5;       // rad/s
  double settle_s = 0.4;             // head still before the hand moves
  double close_s = 0.6;              // gripper closing time
};

// Grasp tilt for each robot: the tilt at which the robot's wrist reaches top-down grasps
// over the table (chosen with the IK; see the scenario tests).
PickExpertSettings PickSettingsFor(const kinematics::RobotModel& robot);

class PickExpert : public Expert {
 public:
  PickExpert(const engine::WorldModel& model, int num_envs, PickExpertSettings settings);
  void Reset(const engine::WorldModel& model, const engine::BatchState& state, int env) override;
  void Act(const engine::WorldModel& model, const engine::BatchState& state, int env,
           kinematics::Action& action) override;

  enum class Phase { kLook, kSettle, kApproach, kDescend, kClose, kLift };
  Phase phase(int env) const { return memory_[env].phase; }

 private:
  struct EnvMemory {
    Phase phase = Phase::kLook;
    int phase_start_step = 0;
    kinematics::Side side = kinematics::Side::kLeft;
    std::array<RigidTransform, 2> hand_command;  // IK link targets, canonical frame
    std::array<double, 3> neck_command{};
    std::array<double, 3> neck_goal{};
    Vec3 fixated_point = Vec3::Zero();
    std::array<double, 2> gripper_command{-1.0, -1.0};
  };

  void Enter(EnvMemory& m, Phase phase, int step) const;
  RigidTransform GraspPose(const engine::WorldModel& model, const engine::BatchState& state, int env,
                           double height_above) const;
  void UpdateNeck(const engine::WorldModel& model, const engine::BatchState& state, int env, EnvMemory& m) const;

  PickExpertSettings settings_;
  std::vector<EnvMemory> memory_;
};

}  // namespace tavis::scenarios

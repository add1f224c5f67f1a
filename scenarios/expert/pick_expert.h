// A privileged scripted expert that picks one object and lifts it, looking before it reaches
// (the human teleoperator's timing that GALT measures): it first reads the task's cue if there is
// one (fixates a card, watches a light until it turns green), then turns the head to fixate the object
// and lets the neck settle, then plans a grasp the arm can reach and moves the nearer arm above
// the object, descends, closes and lifts. The approach is a straight hand line when the
// controller can track it (checked kinematically beforehand), otherwise a straight joint-space
// path (arm_planner.h); descending and lifting are straight hand lines. All are speed-limited at
// the control rate; the commanded action is the hand pose along the way, as a teleoperator's is.
// A grasp that closes on nothing, or loses the object on the way out, is retried as a
// teleoperator would: open, back out to the pre-grasp, plan again from what is there now with
// another hand orientation.
// A target moved under the approaching hand (the runtime perturbation axis, TaskVars::target_move_tick)
// is noticed from the state: the plan made for where it was is dropped without counting as a
// missed grasp, the hand backs out of its descent and the arm returns to where its first reach
// started (the way it came), and the head re-fixates the target where it now is and settles
// before a new grasp is planned from there, as before the first reach.
// In head-still mode (pick_expert_settings.h) the neck never moves and the hands start as soon as
// the task allows: no cue look, fixation or settling.
// This file is the phase machine and the gaze; grasp_planner.h plans the grasps, hand_motion.h
// moves the hands along the plan.
#pragma once

#include <array>
#include <vector>

#include "scenarios/expert/grasp_planner.h"
#include "scenarios/expert/hand_motion.h"
#include "scenarios/expert/pick_expert_settings.h"
#include "scenarios/scenario.h"

namespace tavis::scenarios::expert {

class PickExpert : public Expert {
 public:
  PickExpert(const engine::WorldModel& model, int num_envs, PickExpertSettings settings);
  void Reset(const engine::WorldModel& model, const engine::BatchState& state, int env) override;
  void Act(const engine::WorldModel& model, const engine::BatchState& state, int env,
           kinematics::Action& action) override;
  Gaze gaze(const engine::BatchState& state, int env) const override;
  bool gave_up(int env) const override { return memory_[env].phase == Phase::kGiveUp; }

  // kWaitToAct: head-still only, the hands wait for the scene to rest and for the go signal.
  // kReplan: the target was moved; the hand backs out before the look and the new plan.
  enum class Phase {
    kWatchCue,
    kLook,
    kSettle,
    kPeek,
    kApproach,
    kDescend,
    kClose,
    kWithdraw,
    kLift,
    kRetreat,
    kGiveUp,
    kWaitToAct,
    kReplan
  };
  Phase phase(int env) const { return memory_[env].phase; }
  // Grasps started in the env's episode so far (retries after a miss count, and so do plans
  // dropped because the target was moved).
  int attempts(int env) const { return memory_[env].attempts; }
  // Plans dropped in the env's episode because the target was moved.
  int replans(int env) const { return memory_[env].replans; }

 private:
  struct EnvMemory {
    Phase phase = Phase::kLook;
    std::size_t scan_index = 0;  // scan points fixated so far
    int phase_start_step = 0;
    kinematics::Side side = kinematics::Side::kLeft;  // the reaching arm
    HandMotion hands;                                 // IK link targets, canonical frame
    std::array<double, 3> neck_command{};
    std::array<double, 3> neck_goal{};
    Vec3 fixated_point = Vec3::Zero();
    std::array<double, 2> gripper_command{-1.0, -1.0};
    GraspPlan grasp;  // the current grasp
    bool peeked = false;
    bool peek_done = false;  // the wrists have held their peek poses, or could not take them
    bool cartesian_approach = false;
    std::vector<bool> failed_candidates;  // per grasp candidate: its grasp missed or dropped the object
    int attempts = 0;
    bool saw_target_move = false;  // the runtime axis's move has been noticed
    bool back_out = false;         // kReplan: the hand backs out to the dropped plan's pre-grasp
    bool returning = false;        // kReplan: the arm is on its way back to reach_start
    ArmJoints reach_start{};       // the reaching arm's joints where its first reach started
    int replans = 0;               // plans dropped because the target moved (not missed grasps)
  };

  void Enter(EnvMemory& m, Phase phase, int step) const;
  // Largest distance of the neck command from its fixation goal, rad.
  static double NeckError(const EnvMemory& m);
  void UpdateNeck(const engine::WorldModel& model, const engine::BatchState& state, int env, EnvMemory& m) const;
  // True if the reaching hand's gripper has closed on nothing (fully shut).
  bool HandIsEmpty(const engine::WorldModel& model, const engine::BatchState& state, int env, const EnvMemory& m) const;
  // Gives up the current grasp: opens the hand and backs out to the pre-grasp (kRetreat).
  void StartRetreat(EnvMemory& m, int step) const;
  // Once the target has been moved (TaskVars::target_move_tick): drops a plan made for where it
  // was (kReplan), or looks again if the head had settled on its old place; nothing before a plan
  // or once holding it.
  void NoticeTargetMove(const engine::BatchState& state, int env, EnvMemory& m, int step) const;
  // kReplan: backs the hand out to the dropped plan's pre-grasp if it had passed it and takes the
  // arm back to where its first reach started, then looks again (head-still: plans at once).
  void BackOutToReplan(const engine::WorldModel& model, const engine::BatchState& state, int env, EnvMemory& m,
                       int step) const;
  // Plans both arms' joint-space paths to their peek poses (an arm that cannot reach its pose
  // keeps still); false if neither can peek.
  bool StartPeek(const engine::WorldModel& model, const engine::BatchState& state, int env, EnvMemory& m) const;
  // The hands' first move once nothing else holds them: the wrist peeks if the task has them,
  // else the reach.
  void StartHands(const engine::WorldModel& model, const engine::BatchState& state, int env, EnvMemory& m,
                  int step) const;
  // True while every enabled dynamic object is still (the dropped objects have landed).
  static bool SceneAtRest(const engine::WorldModel& model, const engine::BatchState& state, int env);
  bool head_still() const { return settings_.mode == ExpertMode::kHeadStill; }
  // Plans the grasp from the current state and starts the approach (or gives up).
  void StartReach(const engine::WorldModel& model, const engine::BatchState& state, int env, EnvMemory& m,
                  int step) const;
  // True if the controller can follow a straight hand line from the current pose to the pre-grasp.
  bool ApproachLineIsTrackable(const engine::WorldModel& model, const engine::BatchState& state, int env,
                               EnvMemory& m) const;

  PickExpertSettings settings_;
  std::vector<EnvMemory> memory_;
};

}  // namespace tavis::scenarios::expert

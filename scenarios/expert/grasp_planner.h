// Planning the pick expert's grasp from the state: a hand orientation and the arm configurations
// of the pre-grasp, the grasp and the held object's way out (withdrawal, lift), solved offline
// (arm_planner.h) so that the expert only has to command hand poses along them.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "engine/batch_state.h"
#include "engine/world_model.h"
#include "kinematics/robot_buffers.h"
#include "kinematics/robot_model.h"
#include "scenarios/expert/pick_expert_settings.h"

namespace tavis::scenarios::expert {

constexpr double kArmClearance = 0.005;  // m: planned gap between the arm and fixed obstacles

// A grasp the arm can reach, as the arm configurations the hand passes through.
struct GraspPlan {
  std::size_t candidate = 0;  // index into PickExpertSettings::grasp_candidates
  bool arm_clear = false;     // the plan keeps the arm clear of the scene's fixed obstacles
  bool withdraws = false;     // an along-hand grasp: withdraw before lifting
  ArmJoints pre{}, grasp{}, withdraw{}, lift{};
};

// The arm that reaches for the env's target: the task's choice, or the one on the object's side.
kinematics::Side ReachSide(const PickExpertSettings& settings, const engine::BatchState& state, int env);

// The preferred grasp of the env's target that `side`'s arm reaches from the current joint
// positions, among the settings' grasp candidates except those flagged in `failed` (indexed like
// them); nullopt if there is none.
std::optional<GraspPlan> PlanGrasp(const engine::WorldModel& model, const engine::BatchState& state, int env,
                                   const PickExpertSettings& settings, kinematics::Side side,
                                   const std::vector<bool>& failed);

}  // namespace tavis::scenarios::expert

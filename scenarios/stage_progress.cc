#include "scenarios/stage_progress.h"

#include <algorithm>
#include <stdexcept>

#include "kinematics/forward_kinematics.h"
#include "kinematics/robot_buffers.h"
#include "scenarios/expert/gaze.h"

namespace tavis::scenarios {

StageProgress::StageProgress(const ScenarioDef& scenario, const engine::WorldModel& model)
    : scenario_(scenario),
      model_(model),
      first_ticks_(scenario.stages.size(), -1),
      best_gaze_error_(scenario.stages.size(), 0.0) {
  CheckFitsRobotBuffers(model.robot);
  for (const StageDef& stage : scenario.stages) {
    if (stage.kind != StageDef::Kind::kCueFixated) {
      cue_objects_.push_back(-1);
      continue;
    }
    try {
      cue_objects_.push_back(model.ObjectIndex(stage.object));
    } catch (const std::out_of_range&) {
      throw std::invalid_argument("task " + scenario.name + ": stage " + stage.name + " names cue '" + stage.object +
                                  "', which its world does not hold");
    }
  }
}

void StageProgress::Start() {
  std::fill(first_ticks_.begin(), first_ticks_.end(), -1);
  seen_target_ = false;
}

void StageProgress::Observe(const engine::BatchState& state, int env) {
  // The furthest-back place the target has been, for kTargetRaised, before this tick's check so
  // that the very tick it is raised from counts.
  const Vec3 target = state.ObjectPosition(env, state.target(env));
  const bool pull_out = scenario_.success.kind == SuccessRule::Kind::kPullOutPast;
  const double back = pull_out ? target.x() : target.z();
  if (!seen_target_) {
    furthest_back_ = back;
    seen_target_ = true;
    // The cues do not move, and the head's pose depends on the neck alone: the closest the neck
    // can bring each cue to the optical axis is fixed for the episode.
    for (std::size_t i = 0; i < scenario_.stages.size(); ++i) {
      if (cue_objects_[i] < 0) continue;
      best_gaze_error_[i] =
          expert::ClosestGazeError(model_.robot, state.q_row(env), state.ObjectPosition(env, cue_objects_[i]));
    }
  }
  furthest_back_ = pull_out ? std::max(furthest_back_, back) : std::min(furthest_back_, back);
  for (std::size_t i = 0; i < scenario_.stages.size(); ++i) {
    if (first_ticks_[i] >= 0) continue;
    if (Reached(scenario_.stages[i], cue_objects_[i], best_gaze_error_[i], state, env))
      first_ticks_[i] = state.control_step[env];
  }
}

std::array<double, 2> StageProgress::HandDistances(const engine::BatchState& state, int env) const {
  const kinematics::RobotModel& robot = model_.robot;
  const int target = state.target(env);
  const Vec3 half = BoundingHalfSize(model_.objects[static_cast<std::size_t>(target)].shape);
  const Vec3 centre = state.ObjectPosition(env, target);
  const Quat orientation = state.ObjectOrientation(env, target);
  std::array<double, 2> distances{};
  LinkPoses X_BL;
  for (const kinematics::Side side : {kinematics::Side::kLeft, kinematics::Side::kRight}) {
    const Vec3 tcp_world = kinematics::ToolCentrePointWorld(robot, state.q_row(env), side, X_BL.data());
    const Vec3 local = orientation.conjugate() * (tcp_world - centre);
    distances[kinematics::Index(side)] = (local.cwiseAbs() - half).cwiseMax(0.0).norm();
  }
  return distances;
}

bool StageProgress::Grasping(double reach_m, const engine::BatchState& state, int env) const {
  const std::array<double, 2> distances = HandDistances(state, env);
  for (const kinematics::Side side : {kinematics::Side::kLeft, kinematics::Side::kRight}) {
    const int hand = kinematics::Index(side);
    const bool closing = state.gripper_command_row(env)[hand] > 0.0;
    const bool holding = state.gripper_gap_row(env)[hand] > model_.robot.gripper.closed_gap + kGripMargin;
    if (closing && holding && distances[static_cast<std::size_t>(hand)] <= reach_m) return true;
  }
  return false;
}

bool StageProgress::Reached(const StageDef& stage, int cue_object, double best_gaze_error,
                            const engine::BatchState& state, int env) const {
  switch (stage.kind) {
    case StageDef::Kind::kCueFixated:
      return expert::GazeError(model_.robot, state.q_row(env), state.ObjectPosition(env, cue_object)) <=
             best_gaze_error + stage.max_angle_rad;
    case StageDef::Kind::kTargetApproached: {
      const std::array<double, 2> distances = HandDistances(state, env);
      return std::min(distances[0], distances[1]) <= stage.distance_m;
    }
    case StageDef::Kind::kTargetGrasped: return Grasping(stage.distance_m, state, env);
    case StageDef::Kind::kTargetRaised: {
      if (!Grasping(kGraspReach, state, env)) return false;
      const Vec3 target = state.ObjectPosition(env, state.target(env));
      const SuccessRule& rule = scenario_.success;
      // Past the rule's threshold counts too: an object that starts near it succeeds sooner.
      if (rule.kind == SuccessRule::Kind::kPullOutPast) {
        return target.x() <= furthest_back_ - stage.distance_m || target.x() < rule.threshold_m;
      }
      return target.z() >= furthest_back_ + stage.distance_m || target.z() > rule.threshold_m;
    }
  }
  return false;
}

}  // namespace tavis::scenarios

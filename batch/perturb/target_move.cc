#include "batch/perturb/target_move.h"

#include <array>
#include <cmath>
#include <optional>
#include <vector>

#include "batch/perturb/scene_clearance.h"
#include "kinematics/forward_kinematics.h"
#include "kinematics/robot_buffers.h"

namespace tavis::batch::perturb {
namespace {

constexpr int kHeadings = 12;  // tried in turn, 30 degrees apart

// Both hands' tool centre points, world frame.
std::array<Vec3, 2> ToolCentrePoints(const kinematics::RobotModel& robot, const engine::BatchState& state, int env) {
  LinkPoses X_BL;
  std::array<Vec3, 2> points;
  for (const kinematics::Side side : kinematics::kSides) {
    points[static_cast<std::size_t>(kinematics::Index(side))] =
        kinematics::ToolCentrePointWorld(robot, state.q_row(env), side, X_BL.data());
  }
  return points;
}

double NearestHand(const std::array<Vec3, 2>& hands, const Vec3& point) {
  return std::min((hands[0] - point).norm(), (hands[1] - point).norm());
}

// The target's centre moved along the first heading the rule allows; nullopt if none does.
std::optional<Vec3> MovedCentre(const engine::WorldModel& model, const scenarios::ScenarioDef& scenario,
                                const engine::BatchState& state, int env, const std::array<Vec3, 2>& hands) {
  const engine::TargetMoveSettings& move = model.episode_perturbation.target_move;
  const int target = state.target(env);
  const std::vector<scenarios::SupportZone> zones = scenario.target_zones(state, env);
  engine::RandomStream rng(model.episode_perturbation.seed, engine::RandomStreamId::kTargetMove,
                           static_cast<uint64_t>(state.episode[static_cast<std::size_t>(env)]));
  const double first_heading = rng.Uniform(-M_PI, M_PI);
  scenarios::expert::OrientedBox box = scenarios::expert::ObjectBox(model, state, env, target);
  const Vec3 centre = box.X.translation();
  for (int k = 0; k < kHeadings; ++k) {
    const double heading = first_heading + 2.0 * M_PI * k / kHeadings;
    const Vec3 moved = centre + move.distance_m * Vec3(std::cos(heading), std::sin(heading), 0.0);
    box.X.translation() = moved;
    bool in_zone = false;
    for (const scenarios::SupportZone& zone : zones) in_zone = in_zone || PointInZone(moved, zone);
    if (in_zone && NearestHand(hands, moved) >= move.trigger_m && ClearOfStaticParts(model, box) &&
        ClearOfObjects(model, state, env, box, target, kTargetMoveClearance, kTargetMoveFixedClearance) &&
        ClearOfRobot(model, state, env, box, kTargetMoveFixedClearance)) {
      return moved;
    }
  }
  return std::nullopt;
}

}  // namespace

void MoveTargetNearHand(const engine::WorldModel& model, const scenarios::ScenarioDef& scenario,
                        engine::BatchState& state, int env, engine::PhysicsWorld& world) {
  const engine::EpisodePerturbation& perturbation = model.episode_perturbation;
  engine::TaskVars& vars = state.task[static_cast<std::size_t>(env)];
  if (!perturbation.moves_target() || vars.target_move_tried) return;
  const int target = state.target(env);
  const std::array<Vec3, 2> hands = ToolCentrePoints(model.robot, state, env);
  if (NearestHand(hands, state.ObjectPosition(env, target)) > perturbation.target_move.trigger_m) return;
  vars.target_move_tried = true;
  const std::optional<Vec3> moved = MovedCentre(model, scenario, state, env, hands);
  if (!moved) return;
  // Teleported kinematically and left at rest, as LIBERO-PRO's moving target is.
  const Quat orientation = state.ObjectOrientation(env, target);
  world.SetObject(target, *moved, orientation, true);
  double* pose = state.object_pose_row(env, target);
  for (int k = 0; k < 3; ++k) pose[k] = (*moved)[k];
  double* velocity = state.object_velocity_row(env, target);
  std::fill(velocity, velocity + engine::kObjectVelocitySize, 0.0);
  vars.target_move_tick = state.control_step[static_cast<std::size_t>(env)];
}

}  // namespace tavis::batch::perturb

// The runtime perturbation axis at run time (docs/perturbations.md): LIBERO-PRO's moving target.
#pragma once

#include "engine/batch_state.h"
#include "engine/physics_world.h"
#include "engine/world_model.h"
#include "scenarios/scenario.h"

namespace tavis::batch::perturb {

// m: the least gap between the moved target and any other movable object (the tasks' own
// placements keep their objects apart by more), and between it and a fixed object (a box's walls,
// a cue) or the robot.
inline constexpr double kTargetMoveClearance = 0.03;
inline constexpr double kTargetMoveFixedClearance = 0.01;

// Once per episode, at the first control tick a hand's tool centre point comes within trigger_m
// of the target's centre, moves the target distance_m horizontally, keeping its orientation and
// height, at rest, in the physics (`world`) and the state, and records the tick
// (TaskVars::target_move_tick). The direction is a heading drawn from the episode's own stream
// (seed, RandomStreamId::kTargetMove, episode), or the first of the eleven after it, 30 degrees
// apart, for which the moved centre stays in one of the task's target zones, the target clear of
// the static parts, kTargetMoveClearance from every other movable object and
// kTargetMoveFixedClearance from every fixed one and from the robot, and both
// tool centre points at least trigger_m from it (it is never moved into or toward a hand). With no such direction it
// stays. Nothing without a runtime level, or once the hand has come near (TaskVars::target_move_tried).
void MoveTargetNearHand(const engine::WorldModel& model, const scenarios::ScenarioDef& scenario,
                        engine::BatchState& state, int env, engine::PhysicsWorld& world);

}  // namespace tavis::batch::perturb

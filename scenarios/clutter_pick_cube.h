// clutter-pick-cube (TAVIS-Head, reference 4.3): find the red cube among four YCB objects on
// the table and pick it up; and its TAVIS-Hands variant without the head image.
#pragma once

#include "scenarios/object_placement.h"
#include "scenarios/scenario.h"
#include "scenarios/split.h"

namespace tavis::scenarios {

ScenarioDef ClutterPickCube();

// blocked-clutter-pick-cube (TAVIS-Hands, reference 4.8): the same task with the head camera's
// image black; the head still moves.
ScenarioDef BlockedClutterPickCube();

// Object ranges of the clutter tables, shared by clutter-pick-lift (reference 4.3, 4.4).
PlacementRanges ClutterPlacementRanges(Split split);

// The scene perturbation axes' places on the clutter tables (ScenarioDef::distractor_zones,
// target_zones), shared by clutter-pick-lift: distractors stand behind the clutter as the robot
// sees it, beyond the widest split's placements, where no reach passes; a moved target stays in
// the widest split's placement area.
std::vector<SupportZone> ClutterDistractorZones(const engine::BatchState& state, int env);
std::vector<SupportZone> ClutterTargetZones(const engine::BatchState& state, int env);

}  // namespace tavis::scenarios

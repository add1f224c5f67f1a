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

}  // namespace tavis::scenarios

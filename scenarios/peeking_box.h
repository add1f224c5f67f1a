// peeking-box (TAVIS-Hands, reference 4.6): a YCB object inside a lidded box on the table whose
// left or right side wall is missing; from the front both look the same, so a wrist camera must
// peek at the sides to find the opening before reaching in.
#pragma once

#include "scenarios/scenario.h"

namespace tavis::scenarios {

// The task's own variables of an episode (task_state.h).
struct PeekingBoxVars {
  int open_side = 0;   // +1 the robot's left (+y) wall is missing, -1 the right
  int wall_back = -1;  // the box's back and front walls' object indices, found by name at reset
  int wall_front = -1;
};

ScenarioDef PeekingBox();

}  // namespace tavis::scenarios

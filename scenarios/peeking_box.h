// peeking-box (TAVIS-Hands, reference 4.6): a YCB object inside a lidded box on the table whose
// left or right side wall is missing; from the front both look the same, so a wrist camera must
// peek at the sides to find the opening before reaching in.
#pragma once

#include "scenarios/scenario.h"

namespace tavis::scenarios {

ScenarioDef PeekingBox();

}  // namespace tavis::scenarios

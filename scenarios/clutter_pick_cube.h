// clutter-pick-cube (TAVIS-Head, reference 4.3): find the red cube among four YCB objects on
// the table and pick it up.
#pragma once

#include "scenarios/scenario.h"

namespace tavis::scenarios {

ScenarioDef ClutterPickCube();

}  // namespace tavis::scenarios

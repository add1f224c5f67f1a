// occluded-reach (TAVIS-Hands, reference 4.7): one YCB object behind a portrait monitor standing
// on the table; the arm must reach around the screen to pick it up and lift it.
#pragma once

#include "scenarios/scenario.h"

namespace tavis::scenarios {

ScenarioDef OccludedReach();

}  // namespace tavis::scenarios

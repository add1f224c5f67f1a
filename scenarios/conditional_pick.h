// conditional-pick (TAVIS-Head, reference 4.1): two YCB objects left and right of a cue card;
// a red card means pick the left object, a green card the right one.
#pragma once

#include "scenarios/scenario.h"

namespace tavis::scenarios {

ScenarioDef ConditionalPick();

}  // namespace tavis::scenarios

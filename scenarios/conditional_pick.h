// conditional-pick (TAVIS-Head, reference 4.1): two YCB objects left and right of a cue card;
// a red card means pick the left object, a green card the right one.
#pragma once

#include "scenarios/scenario.h"

namespace tavis::scenarios {

// The task's own variables of an episode (task_state.h).
struct ConditionalPickVars {
  bool card_is_red = false;  // red -> the left object, green -> the right one
};

ScenarioDef ConditionalPick();

}  // namespace tavis::scenarios

// wait-then-act (TAVIS-Head, reference 4.2): one YCB object and a red signal light that turns
// green after a random delay; the object counts as picked only once the light is green.
#pragma once

#include "scenarios/scenario.h"

namespace tavis::scenarios {

// The task's own variables of an episode (task_state.h).
struct WaitThenActVars {
  int light = -1;          // the signal light's object index, found by name at reset
  int go_policy_step = 0;  // policy step (20 Hz) at which the light turns green
  bool go = false;         // the light has turned green
};

ScenarioDef WaitThenAct();

}  // namespace tavis::scenarios

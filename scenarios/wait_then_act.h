// wait-then-act (TAVIS-Head, reference 4.2): one YCB object and a red signal light that turns
// green after a random delay; the object counts as picked only once the light is green.
#pragma once

#include "scenarios/scenario.h"

namespace tavis::scenarios {

ScenarioDef WaitThenAct();

}  // namespace tavis::scenarios

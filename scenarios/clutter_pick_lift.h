// clutter-pick-lift (TAVIS-Head, reference 4.4): five YCB objects on the table; the prompt names
// one of them (three phrasings per object), which must be lifted.
#pragma once

#include "scenarios/scenario.h"

namespace tavis::scenarios {

ScenarioDef ClutterPickLift();

}  // namespace tavis::scenarios

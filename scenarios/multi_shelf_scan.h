// multi-shelf-scan (TAVIS-Head, reference 4.5): five YCB objects in five of the six slots of an
// open three-shelf cabinet (no table); the prompt names one, which must be pulled out past the
// shelf front.
#pragma once

#include "scenarios/scenario.h"

namespace tavis::scenarios {

ScenarioDef MultiShelfScan();

}  // namespace tavis::scenarios

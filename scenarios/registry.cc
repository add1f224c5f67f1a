#include "scenarios/registry.h"

#include <stdexcept>

#include "scenarios/clutter_pick_cube.h"
#include "scenarios/conditional_pick.h"
#include "scenarios/clutter_pick_lift.h"
#include "scenarios/multi_shelf_scan.h"
#include "scenarios/occluded_reach.h"
#include "scenarios/peeking_box.h"
#include "scenarios/wait_then_act.h"

namespace tavis::scenarios {

const std::vector<ScenarioDef>& AllScenarios() {
  static const std::vector<ScenarioDef> scenarios = {
      ConditionalPick(),
      WaitThenAct(),
      ClutterPickCube(),
      ClutterPickLift(),
      MultiShelfScan(),
      PeekingBox(),
      OccludedReach(),
      BlockedClutterPickCube(),
  };
  return scenarios;
}

const ScenarioDef& FindScenario(const std::string& name) {
  std::string known;
  for (const ScenarioDef& scenario : AllScenarios()) {
    if (scenario.name == name) return scenario;
    known += (known.empty() ? "" : ", ") + scenario.name;
  }
  throw std::invalid_argument("unknown task '" + name + "' (known: " + known + ")");
}

}  // namespace tavis::scenarios

#include "scenarios/registry.h"

#include <stdexcept>

#include "scenarios/clutter_pick_cube.h"
#include "scenarios/clutter_pick_lift.h"
#include "scenarios/conditional_pick.h"
#include "scenarios/multi_shelf_scan.h"
#include "scenarios/occluded_reach.h"
#include "scenarios/peeking_box.h"
#include "scenarios/wait_then_act.h"

namespace tavis::scenarios {

const std::vector<ScenarioDef>& AllScenarios() {
  static const std::vector<ScenarioDef> scenarios = {
      ClutterPickLift(), ClutterPickCube(), ConditionalPick(), WaitThenAct(),
      MultiShelfScan(),  PeekingBox(),      OccludedReach(),   BlockedClutterPickCube(),
  };
  return scenarios;
}

std::string KnownTasks() {
  std::string known;
  for (const ScenarioDef& scenario : AllScenarios()) known += (known.empty() ? "" : ", ") + scenario.name;
  return known;
}

const ScenarioDef& FindScenario(const std::string& name) {
  for (const ScenarioDef& scenario : AllScenarios()) {
    if (scenario.name == name) return scenario;
  }
  throw std::invalid_argument("unknown task '" + name + "' (known: " + KnownTasks() + ")");
}

std::vector<const ScenarioDef*> SuiteScenarios(Suite suite) {
  std::vector<const ScenarioDef*> scenarios;
  for (const ScenarioDef& scenario : AllScenarios()) {
    if (scenario.suite == suite) scenarios.push_back(&scenario);
  }
  return scenarios;
}

}  // namespace tavis::scenarios

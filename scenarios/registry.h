// The explicit table of tasks.
#pragma once

#include <string>
#include <vector>

#include "scenarios/scenario.h"

namespace tavis::scenarios {

const std::vector<ScenarioDef>& AllScenarios();
// Throws std::invalid_argument naming the task and listing the known ones.
const ScenarioDef& FindScenario(const std::string& name);

}  // namespace tavis::scenarios

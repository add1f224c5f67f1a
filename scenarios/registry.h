// The explicit table of tasks, in the order of the paper's result tables (reference 10.4):
// TAVIS-Head, then TAVIS-Hands.
#pragma once

#include <string>
#include <vector>

#include "scenarios/scenario.h"

namespace tavis::scenarios {

const std::vector<ScenarioDef>& AllScenarios();
// Throws std::invalid_argument naming the task and listing the known ones.
const ScenarioDef& FindScenario(const std::string& name);
// The suite's tasks, in table order.
std::vector<const ScenarioDef*> SuiteScenarios(Suite suite);
// Every task's name, comma-separated, for --help texts and errors.
std::string KnownTasks();

}  // namespace tavis::scenarios

// `tavis eval`'s options for an evaluation cell's settings, made from the table that declares
// them (batch/cell/cell_settings.h: flag, help text, range, default, the policies each is for),
// and errors naming the flag a user typed where the library names the setting.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "batch/cell/cell_plan.h"
#include "batch/cell/cell_settings.h"

namespace tavis::tools {

// An option bound to `cell` for every setting the table gives an option of its own (not the
// ones a command adds by hand: EvalOption::kByHand), in the table's order.
void AddCellOptions(CLI::App& command, batch::cell::EvaluationCellConfig& cell);

// Refused rather than ignored: a setting's flag given with a policy it is not for throws
// std::invalid_argument ("--keys applies to --policy openpi only, got --policy expert").
void RefuseOptionsOfOtherPolicies(const CLI::App& command, const std::string& policy);

// batch::cell::PlanCell, with a bad setting named by its flag ("--server must name ...").
batch::cell::CellPlan PlanCellNamingFlags(const batch::cell::EvaluationCellConfig& cell);

}  // namespace tavis::tools

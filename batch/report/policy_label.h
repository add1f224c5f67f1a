// The policy label a cell's results carry: what `tavis table` and `tavis compare` keep cells of
// different policies apart by, and what their --label picks.
#pragma once

#include <string>

#include "batch/report/results_table.h"

namespace tavis::batch::report {

// A cell's label: its folder's policy.json "label" (written by `tavis sweep`), else its policy's
// name (summary.json's "policy"), else "unlabelled". Throws std::runtime_error naming policy.json
// when it is there without a string "label".
std::string PolicyLabelOf(const CellCounts& cell);

}  // namespace tavis::batch::report

// The stage funnel section of `tavis table`: per task and table column, how many episodes reached
// each of the task's stages (and every stage before it), succeeded, and ended in a simulator
// fault (physics blow-up), read from the cells' summary.json ("stages", "simulator_faults"; a
// summary written before those keys has no stages and its faults are read from "ends").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "batch/report/results_table.h"

namespace tavis::batch::report {

struct FunnelCount {
  std::string stage;
  int64_t reached = 0;
};

// One cell's funnel; throws std::runtime_error naming the file and the malformed key.
struct CellFunnel {
  std::vector<FunnelCount> stages;
  int64_t simulator_faults = 0;
};
CellFunnel ReadCellFunnel(const std::string& summary_path);

// A Markdown section (a heading, a table and a note): a row per task and column of `table` that
// has episodes, cells of several seeds pooled as the table pools them.
std::string FormatFunnelMarkdown(const ResultsTable& table, const std::vector<CellCounts>& cells);

}  // namespace tavis::batch::report

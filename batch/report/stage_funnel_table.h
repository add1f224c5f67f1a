// The stage funnel section of `tavis table`: per task, robot and split, each stage's share of the
// episodes under every camera side by side (reached with every earlier stage that applies, and
// alone), then per table column the episodes, success rate and simulator faults (physics
// blow-ups): the sweep's tables (stage_funnel_section.h), read from the cells' summary.json
// ("stages", "simulator_faults"; a summary written before those keys has no stages and its faults
// are read from "ends"; one written before "applies" and "reached_alone" counts every stage as
// applying and has no alone counts).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "batch/report/results_table.h"

namespace tavis::batch::report {

struct FunnelCount {
  std::string stage;
  bool applies = true;
  std::optional<int64_t> reached;        // none where the stage does not apply
  std::optional<int64_t> reached_alone;  // none there too, or in a summary written before it
};

// One cell's funnel; throws std::runtime_error naming the file and the malformed key.
struct CellFunnel {
  std::vector<FunnelCount> stages;
  int64_t simulator_faults = 0;
};
CellFunnel ReadCellFunnel(const std::string& summary_path);

// A Markdown section (a heading and the two tables with their notes): rows for each task and
// column of `table` that has episodes, cells of several seeds pooled as the table pools them.
std::string FormatFunnelMarkdown(const ResultsTable& table, const std::vector<CellCounts>& cells);

}  // namespace tavis::batch::report

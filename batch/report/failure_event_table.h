// The failure events and motion quality section of `tavis table`: the sweep's tables
// (failure_event_section.h) made from the episodes.jsonl beside each cell's summary.json (a cell
// without records, or with records written before events existed, adds nothing), cells of several
// seeds pooled as the table pools them.
#pragma once

#include <string>
#include <vector>

#include "batch/report/results_table.h"

namespace tavis::batch::report {

// A Markdown section (a heading and the two tables with their notes); empty when no cell has
// events recorded. Throws std::runtime_error naming the file of a malformed record.
std::string FormatEventsMarkdown(const std::vector<CellCounts>& cells);

}  // namespace tavis::batch::report

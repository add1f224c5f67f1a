// The gaze section of `tavis table`: the sweep's gaze tables (gaze_section.h: verified GALT, gaze
// on target, the task's anchors) made from the episodes.jsonl beside each cell's summary.json (a
// cell without records, or whose records hold no traced gaze, adds nothing), cells of several
// seeds pooled as the table pools them.
#pragma once

#include <string>
#include <vector>

#include "batch/report/results_table.h"

namespace tavis::batch::report {

// A Markdown section (a heading and the two tables with their notes); empty when no cell has a
// traced gaze. Throws std::runtime_error naming the file of a malformed record.
std::string FormatGazeMarkdown(const std::vector<CellCounts>& cells);

}  // namespace tavis::batch::report

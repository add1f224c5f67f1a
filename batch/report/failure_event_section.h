// The sweep's failure events and motion quality (batch/cell/failure_events.h, motion_quality.h):
// per policy label, task, robot, split and camera (seeds pooled), the episodes each event fired
// in, and the medians of each arm's path length, RMS jerk and SPARC. summary.json's
// "failure_events" section and the tables "failure_events" and "motion_quality", which the HTML
// report shows with the others.
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "batch/report/sweep_summary.h"
#include "batch/report/sweep_tables.h"

namespace tavis::batch::report {

// Rows of one label's cells: {task, robot, split, camera, episodes, events: {event: episodes it
// fired in, null where it cannot fire}, motion: {left|right: {path_m, jerk_rms, sparc}}}, in the
// cells' order (cell/event_record.h writes the same for one cell).
nlohmann::ordered_json FailureEventRows(const std::vector<CellEpisodes>& cells);

// The tables of such rows, each also naming its "label".
std::vector<TextTable> FailureEventTables(const nlohmann::ordered_json& rows);

}  // namespace tavis::batch::report

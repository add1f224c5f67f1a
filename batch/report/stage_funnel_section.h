// The sweep's stage funnel: per policy label, task, robot, split and camera (seeds pooled), the
// episodes that reached each of the task's stages and every stage before it, the successes, and
// the simulator faults (physics blow-ups, counted as failures in every success rate) apart from
// the policy's failures. summary.json's "stages" section and the tables' "stage_funnel".
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "batch/report/sweep_summary.h"
#include "batch/report/sweep_tables.h"

namespace tavis::batch::report {

// Rows of one label's cells: {task, robot, split, camera, episodes, successes, simulator_faults,
// stages: [{stage, reached}]}, in the cells' order.
nlohmann::ordered_json StageFunnelRows(const std::vector<CellEpisodes>& cells);

// The table of summary["stages"].
TextTable StageFunnelTable(const nlohmann::ordered_json& summary);

}  // namespace tavis::batch::report

// The sweep's stage funnel: per policy label, task, robot, split and camera (seeds pooled), the
// episodes that reached each of the task's stages and every earlier stage that applies under the
// camera protocol, those that reached it on its own, the successes, and the simulator faults
// (physics blow-ups, counted as failures in every success rate) apart from the policy's failures.
// summary.json's "stages" section and the tables "stage_funnel" (the cameras side by side, a row
// per stage) and "stage_funnel_episodes"; `tavis table` prints the same tables.
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "batch/report/sweep_summary.h"
#include "batch/report/sweep_tables.h"

namespace tavis::batch::report {

// Rows of one label's cells: {task, robot, split, camera, episodes, successes, simulator_faults,
// stages: [{stage, applies, reached, reached_alone}]} (stage_record.h: a gaze stage does not apply
// under a fixed view; its counts are null), in the cells' order.
nlohmann::ordered_json StageFunnelRows(const std::vector<CellEpisodes>& cells);

// The tables of such rows, each also naming its "label": "stage_funnel", a row per label, task,
// robot, split and stage with two columns per camera present (the percent of its episodes that
// reached the stage and every earlier one that applies, and that reached it alone; "n/a" where
// the stage does not apply, "-" where the camera has no cells or a count is unknown), and
// "stage_funnel_episodes", a row per label, task, robot, split and camera with its episodes,
// success rate and simulator faults.
std::vector<TextTable> StageFunnelTables(const nlohmann::ordered_json& rows);

}  // namespace tavis::batch::report

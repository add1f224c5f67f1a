// Camera sets paired with head (camera_protocol.h): per policy label, task, robot, split and camera
// set other than head and fixed (fixed has its own "paired" section), episode i under the set
// against episode i under head, over every seed both cells ran: counts of both / head only / set
// only / neither and McNemar's exact p. summary.json's "paired_camera_sets" and its table.
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "batch/report/sweep_summary.h"
#include "batch/report/sweep_tables.h"

namespace tavis::batch::report {

// Rows of one label's cells: {task, robot, split, camera, pairs, both, head_only, set_only,
// neither, head_rate, set_rate, difference, mcnemar_p}.
nlohmann::ordered_json CameraSetPairRows(const std::vector<CellEpisodes>& cells);

TextTable CameraSetPairTable(const nlohmann::ordered_json& summary);

}  // namespace tavis::batch::report

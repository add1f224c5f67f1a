// Figure 4's dataset reference: the GALT of the LeRobot datasets that a spec's
// figures.galt_reference_datasets maps TAVIS-Head tasks to, in the form SweepSummaryJson takes.
#pragma once

#include <nlohmann/json.hpp>

namespace tavis::batch::sweep {

// null when `figures` (SweepSpec::figures) names no dataset; otherwise {source, datasets: {task:
// DIR}, tasks: {task: [seconds, ...]}}, each task's values those `tavis galt --dataset DIR` detects
// (dataset::reader::DatasetGaltSeconds: every episode at the dataset's fps, reason ok or ok_post_anchor).
// `source` is the folder when every task names the same one, otherwise "datasets". Throws
// std::runtime_error naming the key and the file when a dataset cannot be read.
nlohmann::ordered_json DatasetGaltReference(const nlohmann::ordered_json& figures);

}  // namespace tavis::batch::sweep

// The sweep's gaze (batch/cell/gaze_fixation.h, gaze_anchors.h): per policy label, task, robot,
// split and camera (seeds pooled), the verified GALT, the gaze-on-target ratio, look-before-reach
// and the distributions of the task's gaze anchors over the successful episodes, with the GALT
// values verified and not, which the gaze figures draw (gaze_figures.h). summary.json's "gaze"
// section and the tables "gaze" and "gaze_anchors", which the HTML report and `tavis table` show.
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "batch/report/sweep_summary.h"
#include "batch/report/sweep_tables.h"

namespace tavis::batch::report {

// Rows of one label's cells with a traced head: {task, robot, split, camera, gaze: the cells'
// pooled gaze block (cell::GazeBlockJson: n_episodes, n_with_galt, n_verified, verified_fraction,
// galt_verified_median_s, reasons, gaze_on_target_ratio_mean, cue_before_reach_fraction, anchors),
// galt_verified_values_s, galt_unverified_values_s (the GALT values of the successful episodes whose
// verification failed)}, in the cells' order.
nlohmann::ordered_json GazeRows(const std::vector<CellEpisodes>& cells);

// The tables of such rows, each also naming its "label": "gaze" (a row per setting) and
// "gaze_anchors" (a row per setting and anchor).
std::vector<TextTable> GazeTables(const nlohmann::ordered_json& rows);

}  // namespace tavis::batch::report

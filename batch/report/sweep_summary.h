// The numbers of a sweep, computed once from its cells' episode records into summary.json; the
// tables and the HTML report are written from this JSON, so their numbers are its numbers.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/cell/episode_recorder.h"
#include "batch/cell/evaluation_cell.h"

namespace tavis::batch::report {

struct CellEpisodes {
  std::string id;
  cell::EvaluationCellConfig config;
  std::vector<cell::EpisodeRecord> episodes;  // in episode order
  std::string label;                          // the policy's label (empty: its policy name)
  std::string seed_group;                     // empty: none
  nlohmann::ordered_json server_metadata = nlohmann::ordered_json::array();  // what its servers reported
};

// The human teleoperators' mean GALT per robot (reference 11.3), marked on the GALT plots.
inline constexpr double kHumanGaltGr1t2 = 2.57;
inline constexpr double kHumanGaltReachy2 = 2.10;

// summary.json: "spec" (as given), "cells" (per cell: counts, rate, Wilson interval, the lengths of
// its successful episodes in seconds at 20 Hz with mean/median/std, its GALT summary and values),
// "success" (per suite: the paper-layout table's columns, task rows and suite means, and its
// id - ood columns per robot and camera, in rate differences),
// "id_minus_ood" (per task, robot, camera and ood split, in points), "paired" (head vs fixed per
// task, robot and split over matched episodes, McNemar's exact p), "galt" (per robot, task and
// split over the head cells), "failure_events" (failure_event_section.h), "gaze" (gaze_section.h), "stages" (the stage
// funnel and simulator faults per task, robot, split and camera, stage_funnel_section.h), "paired_camera_sets" (each
// camera set but fixed vs head on matched episodes, camera_set_pairs.h). Cells of several seeds are pooled in
// everything but "cells". Every section but "cells" is computed per policy label and each of its rows names its
// "label": cells of different labels are never pooled. "labels" lists them; "seed_groups" gives, for each group of
// checkpoints, every rate's mean and spread across them (evaluation seeds pool within a checkpoint); "figures" and
// "headline" hold the paper's Figure 3, Figure 4 and headline numbers (paper_figures.h) for the choices in
// spec["figures"], and "gaze_figures" the gaze figures' numbers (gaze_figures.h). `galt_reference` holds per task a
// reference's GALT values for Figure 4 (e.g. a dataset's), used when the spec names no label.
// No timing: the same episodes give the same bytes.
nlohmann::ordered_json SweepSummaryJson(const nlohmann::ordered_json& spec, const std::vector<CellEpisodes>& cells,
                                        const nlohmann::ordered_json& galt_reference = nullptr);

}  // namespace tavis::batch::report

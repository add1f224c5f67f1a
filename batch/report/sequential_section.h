// The sweep's sequential paired test in its results (docs/sweeps.md, "Sequential paired
// testing"): summary.json's "sequential" (present only when the spec turns the test on), its
// table tables/sequential_pairs and the report's paragraph. Computed again from the cells' records,
// as every section: per pair the decision at the look it stopped at, the episodes each cell ran
// and the episodes the early stop saved.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/report/sequential_pairs.h"
#include "batch/report/sweep_summary.h"
#include "batch/report/sweep_tables.h"

namespace tavis::batch::report {

// {settings, pairs: [{kind, first, second, first_label, second_label, task, robot, split,
// first_camera, second_camera, seed, stopped_at, cap, stopped_early, outcome, decided_at,
// first_only, second_only, e_value, episodes_saved}], cells_in_pairs, cells_stopped_early,
// episodes_run, episodes_cap, episodes_saved}. A pair's episodes_saved counts both its cells; the
// totals count each cell once.
nlohmann::ordered_json SequentialSection(const std::vector<CellEpisodes>& cells, const SequentialSettings& settings);

TextTable SequentialTable(const nlohmann::ordered_json& summary);

// The report's paragraph: how many pairs stopped early and the episodes saved ("" without the test).
std::string SequentialHtml(const nlohmann::ordered_json& summary);

}  // namespace tavis::batch::report

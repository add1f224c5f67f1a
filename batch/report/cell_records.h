// The records of `tavis table`'s cells, read from the episodes.jsonl beside each summary.json and
// grouped by policy label, for the table's sections that need episodes (failure events, gaze):
// cells of several seeds are pooled by those sections as the table pools them.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/cell/episode_recorder.h"
#include "batch/report/results_table.h"
#include "batch/report/sweep_summary.h"

namespace tavis::batch::report {

struct LabelCells {
  std::string label;
  std::vector<CellEpisodes> cells;
};

// Per policy label, in order of first appearance, its cells with records, each holding the
// records `keep` accepts (a record written before a field existed lacks it); a cell left without
// records, or of a split or camera this program does not know, is left out. Throws
// std::runtime_error naming the file of a malformed record.
std::vector<LabelCells> ReadCellRecordsByLabel(const std::vector<CellCounts>& cells,
                                               const std::function<bool(const cell::EpisodeRecord&)>& keep);

// The rows `rows_of` makes of each label's cells, each with its "label" first, labels in order.
nlohmann::ordered_json LabelledRows(
    const std::vector<LabelCells>& labels,
    const std::function<nlohmann::ordered_json(const std::vector<CellEpisodes>&)>& rows_of);

}  // namespace tavis::batch::report

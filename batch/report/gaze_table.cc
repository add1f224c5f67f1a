#include "batch/report/gaze_table.h"

#include "batch/report/cell_records.h"
#include "batch/report/gaze_section.h"
#include "batch/report/sweep_tables.h"

namespace tavis::batch::report {

std::string FormatGazeMarkdown(const std::vector<CellCounts>& cells) {
  const nlohmann::ordered_json rows = LabelledRows(
      ReadCellRecordsByLabel(cells, [](const cell::EpisodeRecord& record) { return record.gaze.traced; }), GazeRows);
  if (rows.empty()) return "";
  std::string text = "\n## Gaze\n";
  for (const TextTable& table : GazeTables(rows)) text += "\n" + ToMarkdown(table);
  return text;
}

}  // namespace tavis::batch::report

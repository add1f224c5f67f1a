#include "batch/report/failure_event_table.h"

#include "batch/report/cell_records.h"
#include "batch/report/failure_event_section.h"
#include "batch/report/sweep_tables.h"

namespace tavis::batch::report {

std::string FormatEventsMarkdown(const std::vector<CellCounts>& cells) {
  // FailureEventRows pools the cells of one task, robot, split and camera (several seeds).
  const nlohmann::ordered_json rows = LabelledRows(
      ReadCellRecordsByLabel(cells, [](const cell::EpisodeRecord& record) { return record.events.has_value(); }),
      FailureEventRows);
  if (rows.empty()) return "";
  std::string text = "\n## Failure events and motion quality\n";
  for (const TextTable& table : FailureEventTables(rows)) text += "\n" + ToMarkdown(table);
  return text;
}

}  // namespace tavis::batch::report

#include "batch/report/failure_event_table.h"

#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>

#include "batch/camera_protocol.h"
#include "batch/cell/cell_record_stream.h"
#include "batch/report/failure_event_section.h"
#include "batch/report/sweep_tables.h"
#include "scenarios/split.h"

namespace tavis::batch::report {

std::string FormatEventsMarkdown(const std::vector<CellCounts>& cells) {
  // Per policy label, in order of first appearance, its cells with events recorded;
  // FailureEventRows pools the cells of one task, robot, split and camera (several seeds).
  std::vector<std::string> labels;
  std::map<std::string, std::vector<CellEpisodes>> by_label;
  for (const CellCounts& counts : cells) {
    const std::filesystem::path records = std::filesystem::path(counts.source).parent_path() / "episodes.jsonl";
    if (!counts.has_records || !std::filesystem::exists(records)) continue;
    CellEpisodes cell;
    cell.config.task = counts.task;
    cell.config.robot = counts.robot;
    try {
      cell.config.split = scenarios::ParseSplit(counts.split);
      cell.config.camera = ParseCameraProtocol(counts.camera);
    } catch (const std::exception&) {
      continue;  // a split or camera this program does not know has no events of its own
    }
    std::ifstream in(records, std::ios::binary);
    for (std::string line; std::getline(in, line);) {
      if (line.empty()) continue;
      try {
        cell.episodes.push_back(cell::ParseEpisodeJsonLine(line));
      } catch (const std::exception& error) {
        throw std::runtime_error(records.string() + ": " + error.what());
      }
      if (!cell.episodes.back().events) cell.episodes.pop_back();
    }
    if (cell.episodes.empty()) continue;
    if (!by_label.count(counts.label)) labels.push_back(counts.label);
    by_label[counts.label].push_back(std::move(cell));
  }
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const std::string& label : labels) {
    for (const nlohmann::ordered_json& row : FailureEventRows(by_label[label])) {
      nlohmann::ordered_json labelled = {{"label", label}};
      labelled.update(row);
      rows.push_back(labelled);
    }
  }
  if (rows.empty()) return "";
  std::string text = "\n## Failure events and motion quality\n";
  for (const TextTable& table : FailureEventTables(rows)) text += "\n" + ToMarkdown(table);
  return text;
}

}  // namespace tavis::batch::report

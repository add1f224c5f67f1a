#include "batch/report/cell_records.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "batch/camera_protocol.h"
#include "batch/cell/cell_record_stream.h"
#include "scenarios/split.h"

namespace tavis::batch::report {

std::vector<LabelCells> ReadCellRecordsByLabel(const std::vector<CellCounts>& cells,
                                               const std::function<bool(const cell::EpisodeRecord&)>& keep) {
  std::vector<LabelCells> labels;
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
      continue;  // a split or camera this program does not know has no records of its own
    }
    std::ifstream in(records, std::ios::binary);
    for (std::string line; std::getline(in, line);) {
      if (line.empty()) continue;
      try {
        cell.episodes.push_back(cell::ParseEpisodeJsonLine(line));
      } catch (const std::exception& error) {
        throw std::runtime_error(records.string() + ": " + error.what());
      }
      if (!keep(cell.episodes.back())) cell.episodes.pop_back();
    }
    if (cell.episodes.empty()) continue;
    auto mine =
        std::find_if(labels.begin(), labels.end(), [&](const LabelCells& l) { return l.label == counts.label; });
    if (mine == labels.end()) mine = labels.insert(labels.end(), LabelCells{counts.label, {}});
    mine->cells.push_back(std::move(cell));
  }
  return labels;
}

nlohmann::ordered_json LabelledRows(
    const std::vector<LabelCells>& labels,
    const std::function<nlohmann::ordered_json(const std::vector<CellEpisodes>&)>& rows_of) {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const LabelCells& label : labels) {
    for (const nlohmann::ordered_json& row : rows_of(label.cells)) {
      nlohmann::ordered_json labelled = {{"label", label.label}};
      labelled.update(row);
      rows.push_back(labelled);
    }
  }
  return rows;
}

}  // namespace tavis::batch::report

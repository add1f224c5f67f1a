#include "batch/dataset/reader/dataset_tasks.h"

#include <cstddef>
#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "batch/dataset/parquet/parquet_reader.h"

namespace tavis::batch::dataset::reader {
namespace fs = std::filesystem;

namespace {

using TaskMap = std::map<std::int64_t, std::vector<std::string>>;

void AddEpisode(TaskMap& tasks, std::int64_t episode, std::vector<std::string> strings, const std::string& where) {
  if (!tasks.emplace(episode, std::move(strings)).second) {
    throw std::runtime_error(where + ": episode_index " + std::to_string(episode) + " listed twice");
  }
}

// v3.0: every meta/episodes/*/*.parquet, in sorted order as LeRobot reads them.
TaskMap ReadParquetTasks(const fs::path& dataset_dir) {
  TaskMap tasks;
  for (const fs::path& path : ParquetFilesUnder(dataset_dir / "meta" / "episodes", "", "")) {
    const parquet::ParquetReader reader(path.string());
    const std::vector<std::int64_t> episodes = reader.ReadColumn<std::int64_t>("episode_index");
    const parquet::ListColumn<std::string> strings = reader.ReadListColumn<std::string>("tasks");
    std::size_t next = 0;
    for (std::size_t row = 0; row < episodes.size(); ++row) {
      const auto first = strings.values.begin() + static_cast<std::ptrdiff_t>(next);
      next += strings.row_lengths[row];
      AddEpisode(tasks, episodes[row],
                 std::vector<std::string>(first, strings.values.begin() + static_cast<std::ptrdiff_t>(next)),
                 path.string() + " row " + std::to_string(row));
    }
  }
  return tasks;
}

// v2.1: meta/episodes.jsonl.
TaskMap ReadJsonlTasks(const fs::path& dataset_dir) {
  TaskMap tasks;
  const fs::path file = dataset_dir / "meta" / "episodes.jsonl";
  std::ifstream in(file);
  if (!in) return tasks;
  int line_number = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::string where = file.string() + ":" + std::to_string(line_number);
    try {
      const nlohmann::json episode = nlohmann::json::parse(line);
      AddEpisode(tasks, episode.at("episode_index").get<std::int64_t>(),
                 episode.at("tasks").get<std::vector<std::string>>(), where);
    } catch (const nlohmann::json::exception& error) {
      throw std::runtime_error(where + ": not an episode object with episode_index and tasks: " + error.what());
    }
  }
  return tasks;
}

}  // namespace

TaskMap ReadEpisodeTasks(const fs::path& dataset_dir, DatasetVersion version) {
  return version == DatasetVersion::kV30 ? ReadParquetTasks(dataset_dir) : ReadJsonlTasks(dataset_dir);
}

}  // namespace tavis::batch::dataset::reader

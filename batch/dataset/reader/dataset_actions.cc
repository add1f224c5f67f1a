#include "batch/dataset/reader/dataset_actions.h"

#include <cmath>
#include <cstddef>
#include <stdexcept>

#include "batch/dataset/parquet/parquet_reader.h"
#include "batch/dataset/reader/dataset_tasks.h"

namespace tavis::batch::dataset::reader {
namespace fs = std::filesystem;

namespace {

// Appends one data file's rows to `episodes`, checking that each row is a finite 19-D action and
// that rows are grouped by episode (increasing across all files) with frame_index 0..T-1.
void AppendDataFile(const fs::path& path, std::vector<EpisodeActions>& episodes) {
  const parquet::ParquetReader reader(path.string());
  const std::vector<std::int64_t> episode_index = reader.ReadColumn<std::int64_t>("episode_index");
  const std::vector<std::int64_t> frame_index = reader.ReadColumn<std::int64_t>("frame_index");
  const parquet::ListColumn<float> action = reader.ReadListColumn<float>("action");
  const auto fail = [&path](std::size_t row, const std::string& what) {
    throw std::runtime_error(path.string() + ": row " + std::to_string(row) + ": " + what);
  };

  const std::size_t first_episode_of_file = episodes.size();
  std::size_t offset = 0;
  for (std::size_t row = 0; row < episode_index.size(); ++row) {
    const std::int64_t episode = episode_index[row];
    const bool continues = episodes.size() > first_episode_of_file && episodes.back().episode_index == episode;
    if (!continues) {
      if (!episodes.empty() && episode <= episodes.back().episode_index) {
        fail(row, "episode_index " + std::to_string(episode) + " after episode " +
                      std::to_string(episodes.back().episode_index) +
                      " (rows must be grouped by episode, in increasing order, each episode in one file)");
      }
      episodes.push_back(EpisodeActions{});
      episodes.back().episode_index = episode;
    }
    EpisodeActions& current = episodes.back();
    if (frame_index[row] != current.num_steps) {
      fail(row, "episode " + std::to_string(episode) + " has frame_index " + std::to_string(frame_index[row]) +
                    ", expected " + std::to_string(current.num_steps) + " (frames must run 0..T-1 in order)");
    }
    if (action.row_lengths[row] != static_cast<std::size_t>(kDatasetActionWidth)) {
      fail(row, "action has " + std::to_string(action.row_lengths[row]) + " values, expected " +
                    std::to_string(kDatasetActionWidth) + " (the canonical action)");
    }
    for (int j = 0; j < kDatasetActionWidth; ++j) {
      const float value = action.values[offset + static_cast<std::size_t>(j)];
      if (!std::isfinite(value)) {
        fail(row, "action[" + std::to_string(j) + "] is " + std::to_string(value) + " (episode " +
                      std::to_string(episode) + ", frame " + std::to_string(frame_index[row]) + ")");
      }
      current.values.push_back(static_cast<double>(value));
    }
    offset += action.row_lengths[row];
    ++current.num_steps;
  }
}

}  // namespace

DatasetActions ReadDatasetActions(const fs::path& dataset_dir) {
  DatasetActions dataset;
  dataset.info = ReadDatasetInfo(dataset_dir);
  for (const fs::path& file : DataFiles(dataset_dir, dataset.info.version)) AppendDataFile(file, dataset.episodes);

  if (static_cast<std::int64_t>(dataset.episodes.size()) != dataset.info.total_episodes) {
    throw std::runtime_error((dataset_dir / "meta" / "info.json").string() + ": total_episodes is " +
                             std::to_string(dataset.info.total_episodes) + " but the data files hold " +
                             std::to_string(dataset.episodes.size()) + " episodes");
  }
  const std::map<std::int64_t, std::vector<std::string>> tasks = ReadEpisodeTasks(dataset_dir, dataset.info.version);
  for (EpisodeActions& episode : dataset.episodes) {
    const auto found = tasks.find(episode.episode_index);
    if (found != tasks.end()) episode.tasks = found->second;
  }
  return dataset;
}

}  // namespace tavis::batch::dataset::reader

#include "tests/batch/dataset/synthetic_dataset.h"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "batch/dataset/parquet/parquet_writer.h"

namespace tavis::batch::dataset::testing {
namespace fs = std::filesystem;

namespace {

std::string Padded(std::int64_t value, int digits) {
  std::string text = std::to_string(value);
  return std::string(static_cast<std::size_t>(std::max(0, digits - static_cast<int>(text.size()))), '0') + text;
}

void WriteJson(const fs::path& path, const nlohmann::ordered_json& json) {
  std::ofstream out(path);
  out << json.dump(2) << "\n";
}

void WriteInfo(const fs::path& dir, std::int64_t total_episodes, const SyntheticDatasetOptions& options) {
  nlohmann::ordered_json info;
  info["codebase_version"] = options.codebase_version;
  info["robot_type"] = options.robot_type ? nlohmann::ordered_json(*options.robot_type) : nlohmann::ordered_json();
  info["total_episodes"] = options.total_episodes.value_or(total_episodes);
  info["fps"] = options.fps;
  info["features"] = {{"action", {{"dtype", "float32"}, {"shape", {19}}, {"names", nullptr}}}};
  fs::create_directories(dir / "meta");
  WriteJson(dir / "meta" / "info.json", info);
}

// v3.0 meta/episodes/chunk-000/file-000.parquet: episode_index and tasks.
void WriteEpisodesParquet(const fs::path& dir, const std::vector<SyntheticEpisode>& episodes) {
  fs::create_directories(dir / "meta" / "episodes" / "chunk-000");
  parquet::ParquetWriter writer((dir / "meta" / "episodes" / "chunk-000" / "file-000.parquet").string(),
                                {parquet::ColumnSpec::Scalar("episode_index", parquet::ValueType::kInt64),
                                 parquet::ColumnSpec::List("tasks", parquet::ValueType::kString)});
  parquet::RowGroupBuilder rows = writer.NewRowGroup(episodes.size());
  std::vector<std::int64_t> indices;
  std::vector<std::string> tasks;
  std::vector<std::size_t> lengths;
  for (const SyntheticEpisode& episode : episodes) {
    indices.push_back(episode.episode_index);
    tasks.insert(tasks.end(), episode.tasks.begin(), episode.tasks.end());
    lengths.push_back(episode.tasks.size());
  }
  rows.Add("episode_index", indices);
  rows.AddList("tasks", tasks, lengths);
  writer.WriteRowGroup(rows);
  writer.Close();
}

// v2.1 meta/episodes.jsonl.
void WriteEpisodesJsonl(const fs::path& dir, const std::vector<SyntheticEpisode>& episodes) {
  std::ofstream out(dir / "meta" / "episodes.jsonl");
  for (const SyntheticEpisode& episode : episodes) {
    out << nlohmann::json{{"episode_index", episode.episode_index},
                          {"tasks", episode.tasks},
                          {"length", episode.num_steps}}
               .dump()
        << "\n";
  }
}

}  // namespace

void WriteDataFile(const fs::path& path, const std::vector<SyntheticEpisode>& episodes, std::int64_t first_index,
                   double fps) {
  fs::create_directories(path.parent_path());
  parquet::ParquetWriter writer(path.string(),
                                {parquet::ColumnSpec::List("action", parquet::ValueType::kFloat),
                                 parquet::ColumnSpec::Scalar("episode_index", parquet::ValueType::kInt64),
                                 parquet::ColumnSpec::Scalar("frame_index", parquet::ValueType::kInt64),
                                 parquet::ColumnSpec::Scalar("index", parquet::ValueType::kInt64),
                                 parquet::ColumnSpec::Scalar("timestamp", parquet::ValueType::kFloat)});
  std::int64_t index = first_index;
  for (const SyntheticEpisode& episode : episodes) {
    const auto steps = static_cast<std::size_t>(episode.num_steps);
    parquet::RowGroupBuilder rows = writer.NewRowGroup(steps);
    std::vector<float> actions(episode.actions.begin(), episode.actions.end());
    std::vector<std::int64_t> frames = episode.frame_index, episode_index(steps, episode.episode_index), global(steps);
    std::vector<float> timestamps(steps);
    if (frames.empty()) {
      for (std::size_t t = 0; t < steps; ++t) frames.push_back(static_cast<std::int64_t>(t));
    }
    for (std::size_t t = 0; t < steps; ++t) {
      global[t] = index++;
      timestamps[t] = static_cast<float>(static_cast<double>(frames[t]) / fps);
    }
    rows.AddList("action", actions, std::vector<std::size_t>(steps, static_cast<std::size_t>(episode.width)));
    rows.Add("episode_index", episode_index);
    rows.Add("frame_index", frames);
    rows.Add("index", global);
    rows.Add("timestamp", timestamps);
    writer.WriteRowGroup(rows);
  }
  writer.Close();
}

void WriteSyntheticDataset(const fs::path& dir, const std::vector<SyntheticEpisode>& episodes,
                           const SyntheticDatasetOptions& options) {
  WriteInfo(dir, static_cast<std::int64_t>(episodes.size()), options);
  std::int64_t index = 0;
  if (options.codebase_version == "v2.1") {
    for (const SyntheticEpisode& episode : episodes) {
      WriteDataFile(dir / "data" / "chunk-000" / ("episode_" + Padded(episode.episode_index, 6) + ".parquet"),
                    {episode}, index, options.fps);
      index += episode.num_steps;
    }
    WriteEpisodesJsonl(dir, episodes);
    return;
  }
  std::size_t next = 0;
  for (std::size_t file = 0; next < episodes.size(); ++file) {
    const std::size_t count = file < options.episodes_per_file.size()
                                  ? static_cast<std::size_t>(options.episodes_per_file[file])
                                  : episodes.size() - next;
    const std::vector<SyntheticEpisode> in_file(episodes.begin() + static_cast<std::ptrdiff_t>(next),
                                                episodes.begin() + static_cast<std::ptrdiff_t>(next + count));
    WriteDataFile(dir / "data" / "chunk-000" / ("file-" + Padded(static_cast<std::int64_t>(file), 3) + ".parquet"),
                  in_file, index, options.fps);
    for (const SyntheticEpisode& episode : in_file) index += episode.num_steps;
    next += count;
  }
  WriteEpisodesParquet(dir, episodes);
}

fs::path GaltVectorDir() { return fs::path(TAVIS_REPO_TEST_DATA_DIR) / "galt"; }

SyntheticEpisode LoadGaltVector(const std::string& name, std::int64_t episode_index) {
  std::ifstream in(GaltVectorDir() / name);
  if (!in) throw std::runtime_error("cannot open " + (GaltVectorDir() / name).string());
  SyntheticEpisode episode;
  episode.episode_index = episode_index;
  for (std::string line; std::getline(in, line);) {
    std::istringstream fields(line);
    for (std::string field; std::getline(fields, field, ',');) episode.actions.push_back(std::stod(field));
    ++episode.num_steps;
  }
  return episode;
}

std::string ExpectedGaltLine(const std::string& name) {
  std::ifstream in(GaltVectorDir() / "expected.jsonl");
  for (std::string line; std::getline(in, line);) {
    if (nlohmann::json::parse(line).at("file") == name) return line;
  }
  throw std::runtime_error("no expected result for " + name);
}

}  // namespace tavis::batch::dataset::testing

// Small LeRobot datasets for tests of dataset readers: meta/info.json, data Parquet files shaped
// as LeRobot writes them (action list<float>[19], episode_index, frame_index, index int64,
// timestamp float) and the episode metadata with each episode's tasks, in the v3.0 or v2.1
// layout; plus the GALT conformance CSVs kept in tests/data/galt.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace tavis::batch::dataset::testing {

struct SyntheticEpisode {
  std::int64_t episode_index = 0;
  std::vector<double> actions;  // num_steps x width, row-major (stored as float32)
  int num_steps = 0;
  int width = 19;
  std::vector<std::int64_t> frame_index;  // empty: 0..num_steps-1
  std::vector<std::string> tasks;
};

struct SyntheticDatasetOptions {
  std::string codebase_version = "v3.0";
  double fps = 60;
  std::optional<std::string> robot_type = "gr1t2";
  // v3.0: how many consecutive episodes each data file chunk-000/file-NNN holds (v2.1: one each).
  std::vector<int> episodes_per_file = {2, 1};
  std::optional<std::int64_t> total_episodes;  // default: the number of episodes written
};

// Writes the dataset under `dir` (created).
void WriteSyntheticDataset(const std::filesystem::path& dir, const std::vector<SyntheticEpisode>& episodes,
                           const SyntheticDatasetOptions& options = {});

// Writes one LeRobot data file holding `episodes` one after another (global index from
// `first_index`, timestamp = frame_index / fps).
void WriteDataFile(const std::filesystem::path& path, const std::vector<SyntheticEpisode>& episodes,
                   std::int64_t first_index = 0, double fps = 60);

// tests/data/galt/NAME (a T x 19 CSV without header) as an episode.
SyntheticEpisode LoadGaltVector(const std::string& name, std::int64_t episode_index);

// tests/data/galt/expected.jsonl's line for NAME, as text.
std::string ExpectedGaltLine(const std::string& name);

// The directory of the copied conformance vectors.
std::filesystem::path GaltVectorDir();

}  // namespace tavis::batch::dataset::testing

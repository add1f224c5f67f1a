#include "batch/sweep/sweep_cell.h"

#include <fstream>
#include <functional>
#include <memory>
#include <utility>

#include <nlohmann/json.hpp>

#include "batch/cell/cell_folder.h"
#include "batch/cell/cell_record_stream.h"
#include "batch/output/atomic_file.h"
#include "batch/rollout/cell_videos.h"
#include "batch/sweep/sequential_stop.h"

namespace tavis::batch::sweep {
namespace {

namespace fs = std::filesystem;

std::optional<nlohmann::json> ReadJson(const fs::path& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    return std::nullopt;
  }
}

}  // namespace

std::optional<nlohmann::json> ReadCellSettings(const fs::path& dir) { return ReadJson(dir / "cell.json"); }

std::optional<std::vector<cell::EpisodeRecord>> ReadCompleteCell(const fs::path& dir, const nlohmann::json& cell_json,
                                                                 int64_t episodes) {
  const std::optional<nlohmann::json> settings = ReadCellSettings(dir);
  const std::optional<nlohmann::json> summary = ReadJson(dir / "summary.json");
  if (!settings || !summary || *settings != cell_json) return std::nullopt;
  std::ifstream in(dir / "episodes.jsonl", std::ios::binary);
  std::vector<cell::EpisodeRecord> records;
  int64_t successes = 0;
  for (std::string line; std::getline(in, line);) {
    try {
      records.push_back(cell::ParseEpisodeJsonLine(line));
    } catch (const std::exception&) {
      return std::nullopt;
    }
    if (records.back().episode != static_cast<int64_t>(records.size()) - 1) return std::nullopt;
    successes += records.back().success ? 1 : 0;
  }
  // A cell the sequential test stopped early holds fewer (checked against its pairs by the results).
  episodes = SequentialEpisodes(dir, episodes);
  if (static_cast<int64_t>(records.size()) != episodes || summary->value("n_episodes", int64_t{-1}) != episodes ||
      summary->value("n_successful", int64_t{-1}) != successes) {
    return std::nullopt;
  }
  return records;
}

cell::CellResult RunCellInto(const cell::CellPlan& plan, const fs::path& dir, int threads,
                             const ProgressCallback& progress, const std::string& label, const std::string& seed_group,
                             const rollout::EpisodeVideoSettings& videos, int64_t stop_before, bool complete_at_stop) {
  cell::CellFolderOptions folder;
  folder.out = dir;
  // A folder with settings continues; anything else there (a cell that failed before writing its
  // settings, or one whose summary does not match its records) starts over.
  folder.resume = fs::exists(dir / "cell.json") && !fs::exists(dir / "summary.json");
  // The sweep's lock keeps other sweeps out; this one keeps out an `eval --resume` of the cell.
  folder.command = "sweep";
  // A cell that failed keeps its folder: the next run of the sweep continues it or starts it over.
  folder.remove_new_folder_on_failure = false;
  folder.threads = threads;
  folder.label = label;
  folder.progress = progress;
  folder.stop_before = stop_before;
  folder.complete_at_stop = complete_at_stop;
  if (!folder.resume) fs::remove_all(dir);
  std::unique_ptr<rollout::CellVideos> films;
  return cell::RunCellInFolder(
      plan, folder, [&](const cell::CellPlan& planned, const std::function<fs::path()>&) -> cell::CellAttachments {
        output::WriteFileAtomically(
            dir / "policy.json", nlohmann::ordered_json({{"label", label}, {"seed_group", seed_group}}).dump(2) + "\n");
        films = std::make_unique<rollout::CellVideos>(videos, planned.config, [&dir] { return dir / "videos"; });
        return {films->Sinks(), [&films](const cell::EpisodeRecord& record) { films->RecordFinished(record); }, nullptr,
                [&films](const std::vector<cell::EpisodeRecord>& resumed) { return films->RecordsKept(resumed); }};
      });
}

}  // namespace tavis::batch::sweep

// One cell of a sweep in its folder, through the eval cell's record stream: a cell interrupted
// after some episodes continues after its complete ones (their records are kept, a torn last line
// is cut), a complete one is recognised by checking its files against its settings.
#pragma once

#include <filesystem>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/cell/cell_plan.h"
#include "batch/cell/episode_recorder.h"
#include "batch/cell/evaluation_cell.h"
#include "batch/episode_driver.h"
#include "batch/rollout/episode_videos.h"

namespace tavis::batch::sweep {

// DIR/cell.json, the settings the cell was run with; nullopt when it is absent or not JSON.
std::optional<nlohmann::json> ReadCellSettings(const std::filesystem::path& dir);

// The cell's records when DIR holds it complete: cell.json equal to `cell_json` (what the cell
// records: cell::CellSettingsJson of its plan), summary.json, and episodes.jsonl with exactly
// episodes 0 .. `episodes` - 1 (fewer for a cell the sequential test stopped: sequential_stop.h)
// whose successes match the summary's count. nullopt otherwise
// (absent, interrupted, or not matching: such a folder is run again).
std::optional<std::vector<cell::EpisodeRecord>> ReadCompleteCell(const std::filesystem::path& dir,
                                                                 const nlohmann::json& cell_json, int64_t episodes);

// Runs the planned cell into DIR (continuing an interrupted one), writes its summary.json last
// and returns the whole cell's result (the kept records first). DIR/policy.json names the
// policy's label and seed group, so that tools reading the folder (`tavis table`) keep labels
// apart. `videos` films the cell's first episodes into DIR/videos (none by default).
// `stop_before` (>= 0) runs only the episodes before it and leaves the cell paused there (as an
// interrupted one), or complete with them when `complete_at_stop` (the sequential test's blocks).
cell::CellResult RunCellInto(const cell::CellPlan& plan, const std::filesystem::path& dir, int threads,
                             const ProgressCallback& progress, const std::string& label, const std::string& seed_group,
                             const rollout::EpisodeVideoSettings& videos = {}, int64_t stop_before = -1,
                             bool complete_at_stop = false);

}  // namespace tavis::batch::sweep

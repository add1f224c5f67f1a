// Writes an evaluation cell's results: DIR/episodes.jsonl (one object per episode), beside it
// DIR/episode_times.jsonl when its episodes were timed (each one's time split, episode_times.h),
// DIR/summary.json, and for a served policy
// DIR/actions/episode_<i>.csv.gz (the actions each episode stepped with, one row per policy step, gzip-compressed, for
// --policy replay and tavis verify) and its request timings. Files are written to a temporary name and renamed, so an
// interrupted run never leaves a half-written result in place of a good one.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "batch/cell/evaluation_cell.h"

namespace tavis::batch::cell {

struct RunInfo {
  int threads = 0;
  int64_t resumed_episodes = 0;  // records taken over from an interrupted run of the cell
};

// All of a cell's results at once (a cell run without streaming its records).
void WriteCellReport(const CellResult& result, const RunInfo& info, const std::string& out_dir);

// DIR/summary.json alone, for a cell whose records were streamed (CellRecordStream).
// `label`: the policy label its provenance names (empty: the policy's name).
void WriteCellSummary(const CellResult& result, const RunInfo& info, const std::string& out_dir,
                      const std::string& label = "");

// An episode's line of episodes.jsonl (no newline).
std::string EpisodeJsonLine(const EpisodeRecord& record, uint64_t seed);

// DIR/actions/episode_<i>.csv.gz: the actions a served policy's episode stepped with, one row per
// policy step, gzip-compressed (2.2x smaller than the plain CSV), for --policy replay.
void WriteReplayCsv(const EpisodeRecord& record, const std::filesystem::path& out_dir);

// One line for the terminal: task, robot, split, policy, success rate with its interval, time,
// and how many episodes ended invalid_action, naming the first.
std::string CellSummaryLine(const CellResult& result);

}  // namespace tavis::batch::cell

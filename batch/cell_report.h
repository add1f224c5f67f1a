// Writes an evaluation cell's results: DIR/episodes.jsonl (one object per episode),
// DIR/summary.json, and for a served policy DIR/actions/episode_<i>.csv (the actions each episode
// stepped with, one row per policy step, for --policy replay) and its request timings. Files are
// written to a temporary name and renamed, so an interrupted run never leaves a half-written
// result in place of a good one.
#pragma once

#include <string>

#include "batch/evaluation_cell.h"

namespace tavis::batch {

struct RunInfo {
  int threads = 0;
};

void WriteCellReport(const CellResult& result, const RunInfo& info, const std::string& out_dir);

// One line for the terminal: task, robot, split, policy, success rate with its interval, time,
// and how many episodes ended invalid_action, naming the first.
std::string CellSummaryLine(const CellResult& result);

}  // namespace tavis::batch

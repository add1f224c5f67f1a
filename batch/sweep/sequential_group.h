// Runs one group of paired cells of a sweep's sequential test (sequential_plan.h) in blocks:
// every cell of the group to the next look (block, 2 block, ..., the cap), then the test on the
// pairs' first n episodes; at the first look where every pair has decided, or at the cap, each
// cell records why it stopped (sequential_stop.h) and is made complete with those n episodes.
// Episode i stays the episode it is without the test (same scene, same record), and a cell is
// paused between blocks exactly as an interrupted one, so a resumed or sharded sweep looks at the
// same n and stops at the same one as an uninterrupted run.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "batch/cell/episode_recorder.h"
#include "batch/report/sequential_pairs.h"
#include "batch/sweep/sweep_spec.h"

namespace tavis::batch::sweep {

struct GroupCell {
  const SweepCell* cell;
  std::filesystem::path dir;
  // Its records when it was complete before this run (it is not run again).
  std::optional<std::vector<cell::EpisodeRecord>> complete;
};

// Runs the cell `member` of the group up to `stop_before` (sweep_cell.h's RunCellInto: paused
// there, or complete when `complete_at_stop`) and returns the whole cell's records.
using RunGroupCell =
    std::function<std::vector<cell::EpisodeRecord>(std::size_t member, int64_t stop_before, bool complete_at_stop)>;

// `pairs` are positions in `cells`. Throws std::runtime_error naming a cell complete with fewer
// or more episodes than the group stops at (a folder from another run).
void RunSequentialGroup(const std::vector<GroupCell>& cells, const std::vector<report::SequentialPair>& pairs,
                        const report::SequentialTestSettings& settings, const RunGroupCell& run);

}  // namespace tavis::batch::sweep

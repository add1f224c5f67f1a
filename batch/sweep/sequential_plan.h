// A sweep's sequential paired test laid over its cells (report/sequential_pairs.h): the pairs, the
// groups that run in blocks and stop together, and where each cell is sharded. A group runs in one
// process, so its cells go to the shard of its first cell; every other cell keeps its own
// position. With the test off every cell keeps its position and nothing changes.
#pragma once

#include <cstddef>
#include <vector>

#include "batch/cell/episode_recorder.h"
#include "batch/report/sequential_pairs.h"
#include "batch/sweep/sweep_spec.h"

namespace tavis::batch::sweep {

struct SequentialPlan {
  std::vector<report::SequentialPair> pairs;     // positions in the sweep's cells
  std::vector<std::vector<std::size_t>> groups;  // ascending positions
  std::vector<std::size_t> shard_position;       // per cell: the position InShard takes
  std::vector<std::ptrdiff_t> group_of;          // per cell: its group, or -1
};

SequentialPlan PlanSequential(const std::vector<SweepCell>& cells, const report::SequentialSettings& settings);

// Throws output::SettingError (key "shard") unless each of the N shards gets a cell or a group.
void RequireShardHoldsUnits(const Shard& shard, const SequentialPlan& plan);

// The pairs of `group` (positions in the sweep) as positions in the group.
std::vector<report::SequentialPair> GroupPairs(const SequentialPlan& plan, std::size_t group);

// The episode count the test stops `group` at, from its cells' outcomes (positions in the
// group): the first look at which every pair has decided, else the cap.
int64_t GroupStop(const std::vector<report::Outcomes>& outcomes, const std::vector<report::SequentialPair>& pairs,
                  int64_t cap, const report::SequentialTestSettings& settings);

// The stop of each cell of a finished sweep (`records` per cell, in order) against its group's
// records: every cell of a group holds the episodes GroupStop gives, every other cell its cap.
// Throws std::runtime_error naming the first cell that does not (a folder edited or mixed from
// other runs).
void RequireSequentialStops(const SequentialPlan& plan, const std::vector<SweepCell>& cells,
                            const std::vector<std::vector<cell::EpisodeRecord>>& records,
                            const report::SequentialTestSettings& settings);

// Success per episode of `records`' first `count`.
report::Outcomes OutcomesOf(const std::vector<cell::EpisodeRecord>& records, int64_t count);

}  // namespace tavis::batch::sweep

#include "batch/sweep/sequential_plan.h"

#include <algorithm>
#include <set>
#include <stdexcept>
#include <string>

#include "batch/output/setting_error.h"

namespace tavis::batch::sweep {

SequentialPlan PlanSequential(const std::vector<SweepCell>& cells, const report::SequentialSettings& settings) {
  std::vector<report::PairingCell> pairing;
  for (const SweepCell& cell : cells) pairing.push_back({&cell.config, cell.label});
  SequentialPlan plan;
  plan.pairs = report::SequentialPairs(pairing, settings);
  plan.groups = report::SequentialGroups(cells.size(), plan.pairs);
  plan.group_of.assign(cells.size(), -1);
  plan.shard_position.resize(cells.size());
  for (std::size_t i = 0; i < cells.size(); ++i) plan.shard_position[i] = i;
  for (std::size_t g = 0; g < plan.groups.size(); ++g) {
    for (const std::size_t i : plan.groups[g]) {
      plan.group_of[i] = static_cast<std::ptrdiff_t>(g);
      plan.shard_position[i] = plan.groups[g].front();
    }
  }
  return plan;
}

void RequireShardHoldsUnits(const Shard& shard, const SequentialPlan& plan) {
  const std::set<std::size_t> units(plan.shard_position.begin(), plan.shard_position.end());
  if (static_cast<std::size_t>(shard.count) <= units.size() || units.size() == plan.shard_position.size()) return;
  throw output::SettingError("shard", "'" + std::to_string(shard.index) + "/" + std::to_string(shard.count) +
                                          "': the sequential test runs " + std::to_string(plan.shard_position.size()) +
                                          " cells as " + std::to_string(units.size()) +
                                          " units (its groups of paired cells stay in one shard): N must be 1 to " +
                                          std::to_string(units.size()));
}

std::vector<report::SequentialPair> GroupPairs(const SequentialPlan& plan, std::size_t group) {
  const std::vector<std::size_t>& members = plan.groups[group];
  const auto local = [&members](std::size_t position) {
    return static_cast<std::size_t>(std::find(members.begin(), members.end(), position) - members.begin());
  };
  std::vector<report::SequentialPair> pairs;
  for (const report::SequentialPair& pair : plan.pairs) {
    if (plan.group_of[pair.first] == static_cast<std::ptrdiff_t>(group))
      pairs.push_back({pair.kind, local(pair.first), local(pair.second)});
  }
  return pairs;
}

report::Outcomes OutcomesOf(const std::vector<cell::EpisodeRecord>& records, int64_t count) {
  report::Outcomes outcomes;
  for (int64_t i = 0; i < count && i < static_cast<int64_t>(records.size()); ++i)
    outcomes.push_back(records[static_cast<std::size_t>(i)].success);
  return outcomes;
}

int64_t GroupStop(const std::vector<report::Outcomes>& outcomes, const std::vector<report::SequentialPair>& pairs,
                  int64_t cap, const report::SequentialTestSettings& settings) {
  for (const int64_t look : report::SequentialLooks(cap, settings.block)) {
    std::vector<report::Outcomes> cut;
    for (const report::Outcomes& cell : outcomes) {
      if (static_cast<int64_t>(cell.size()) < look) return cap;  // not run this far: it did not stop before
      cut.emplace_back(cell.begin(), cell.begin() + look);
    }
    std::vector<std::pair<const report::Outcomes*, const report::Outcomes*>> looked;
    for (const report::SequentialPair& pair : pairs) looked.emplace_back(&cut[pair.first], &cut[pair.second]);
    if (report::EveryPairDecided(looked, settings)) return look;
  }
  return cap;
}

void RequireSequentialStops(const SequentialPlan& plan, const std::vector<SweepCell>& cells,
                            const std::vector<std::vector<cell::EpisodeRecord>>& records,
                            const report::SequentialTestSettings& settings) {
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const int64_t cap = cells[i].config.episodes;
    int64_t expected = cap;
    if (plan.group_of[i] >= 0) {
      const std::size_t group = static_cast<std::size_t>(plan.group_of[i]);
      std::vector<report::Outcomes> outcomes;
      for (const std::size_t member : plan.groups[group]) outcomes.push_back(OutcomesOf(records[member], cap));
      expected = GroupStop(outcomes, GroupPairs(plan, group), cap, settings);
    }
    if (static_cast<int64_t>(records[i].size()) != expected) {
      throw std::runtime_error("cell " + cells[i].id + " holds " + std::to_string(records[i].size()) +
                               " episodes where the sequential test over its pairs stops at " +
                               std::to_string(expected) + ": its folder is not this sweep's run; remove it and rerun");
    }
  }
}

}  // namespace tavis::batch::sweep

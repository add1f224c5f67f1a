#include "batch/sweep/sequential_group.h"

#include <stdexcept>
#include <string>

#include "batch/sweep/sequential_plan.h"
#include "batch/sweep/sequential_stop.h"

namespace tavis::batch::sweep {
namespace {

using Json = nlohmann::ordered_json;

// What DIR/sequential.json of `member` says once the group stops at `stopped_at`.
Json StopJson(const std::vector<GroupCell>& cells, const std::vector<report::SequentialPair>& pairs,
              const std::vector<report::Outcomes>& outcomes, std::size_t member, int64_t stopped_at, int64_t cap,
              const report::SequentialTestSettings& settings) {
  Json pair_list = Json::array();
  bool all_decided = true;
  for (const report::SequentialPair& pair : pairs) {
    const report::SequentialDecision decision =
        report::DecideSequentially(outcomes[pair.first], outcomes[pair.second], settings);
    const bool decided = decision.outcome != report::SequentialOutcome::kUndecided;
    all_decided = all_decided && decided;
    if (pair.first != member && pair.second != member) continue;
    pair_list.push_back({{"kind", pair.kind},
                         {"first", cells[pair.first].cell->id},
                         {"second", cells[pair.second].cell->id},
                         {"outcome", report::ToString(decision.outcome)},
                         {"decided_at", decided ? Json(decision.pairs) : Json()},
                         {"first_only", decision.first_only},
                         {"second_only", decision.second_only},
                         {"e_value", decision.e_value}});
  }
  Json group = Json::array();
  for (const GroupCell& cell : cells) group.push_back(cell.cell->id);
  return {{"stopped_at", stopped_at},
          {"cap", cap},
          {"why", all_decided ? "decided" : "cap"},
          {"alpha", settings.alpha},
          {"block", settings.block},
          {"group", group},
          {"pairs", pair_list}};
}

}  // namespace

void RunSequentialGroup(const std::vector<GroupCell>& cells, const std::vector<report::SequentialPair>& pairs,
                        const report::SequentialTestSettings& settings, const RunGroupCell& run) {
  const int64_t cap = cells.front().cell->config.episodes;
  std::vector<report::Outcomes> outcomes(cells.size());
  for (const int64_t look : report::SequentialLooks(cap, settings.block)) {
    for (std::size_t m = 0; m < cells.size(); ++m) {
      const std::vector<cell::EpisodeRecord> records = cells[m].complete ? *cells[m].complete : run(m, look, false);
      if (static_cast<int64_t>(records.size()) < look) {
        throw std::runtime_error("cell " + cells[m].cell->id + " is complete with " + std::to_string(records.size()) +
                                 " episodes, but the sequential test over its pairs goes on past them: its folder is "
                                 "not this sweep's run; remove it and rerun");
      }
      outcomes[m] = OutcomesOf(records, look);
    }
    std::vector<std::pair<const report::Outcomes*, const report::Outcomes*>> looked;
    for (const report::SequentialPair& pair : pairs) looked.emplace_back(&outcomes[pair.first], &outcomes[pair.second]);
    if (look < cap && !report::EveryPairDecided(looked, settings)) continue;
    for (std::size_t m = 0; m < cells.size(); ++m) {
      if (cells[m].complete) {
        if (static_cast<int64_t>(cells[m].complete->size()) != look)
          throw std::runtime_error("cell " + cells[m].cell->id + " is complete with " +
                                   std::to_string(cells[m].complete->size()) + " episodes where its group stops at " +
                                   std::to_string(look) + ": its folder is not this sweep's run; remove it and rerun");
        continue;
      }
      WriteSequentialStop(cells[m].dir, StopJson(cells, pairs, outcomes, m, look, cap, settings));
      run(m, look, true);
    }
    return;
  }
}

}  // namespace tavis::batch::sweep

#include "batch/report/stage_funnel_section.h"

#include <map>
#include <string>
#include <tuple>

#include "batch/cell/stage_record.h"
#include "scenarios/split.h"

namespace tavis::batch::report {

using Json = nlohmann::ordered_json;

Json StageFunnelRows(const std::vector<CellEpisodes>& cells) {
  using Key = std::tuple<std::string, std::string, std::string, std::string>;
  std::vector<Key> order;
  std::map<Key, std::vector<cell::EpisodeRecord>> episodes;
  for (const CellEpisodes& cell : cells) {
    const Key key{cell.config.task, cell.config.robot, scenarios::ToString(cell.config.split),
                  ToString(cell.config.camera)};
    if (!episodes.count(key)) order.push_back(key);
    std::vector<cell::EpisodeRecord>& pooled = episodes[key];
    pooled.insert(pooled.end(), cell.episodes.begin(), cell.episodes.end());
  }
  Json rows = Json::array();
  for (const Key& key : order) {
    const auto& [task, robot, split, camera] = key;
    const std::vector<cell::EpisodeRecord>& records = episodes[key];
    int64_t successes = 0, faults = 0;
    for (const cell::EpisodeRecord& record : records) {
      successes += record.success ? 1 : 0;
      faults += record.end == engine::EpisodeEnd::kPhysicsBlowUp ? 1 : 0;
    }
    Json stages = Json::array();
    for (const cell::FunnelStep& step : cell::StageFunnel(cell::StageNames(task), records)) {
      stages.push_back({{"stage", step.stage}, {"reached", step.reached}});
    }
    rows.push_back({{"task", task},
                    {"robot", robot},
                    {"split", split},
                    {"camera", camera},
                    {"episodes", static_cast<int64_t>(records.size())},
                    {"successes", successes},
                    {"simulator_faults", faults},
                    {"stages", stages}});
  }
  return rows;
}

TextTable StageFunnelTable(const Json& summary) {
  TextTable table{"stage_funnel",
                  "Stage funnel: episodes (%) that reached each stage and every stage before it",
                  {"policy", "task", "robot", "split", "camera", "episodes", "stages", "success %", "simulator faults"},
                  {},
                  ""};
  for (const Json& row : summary["stages"]) {
    const double episodes = static_cast<double>(row["episodes"].get<int64_t>());
    const auto share = [&](int64_t count) {
      return episodes > 0 ? Percent(static_cast<double>(count) / episodes) : "-";
    };
    std::string stages;
    for (const Json& step : row["stages"]) {
      stages +=
          (stages.empty() ? "" : ", ") + step["stage"].get<std::string>() + " " + share(step["reached"].get<int64_t>());
    }
    table.rows.push_back({row["label"], row["task"], row["robot"], row["split"], row["camera"],
                          std::to_string(row["episodes"].get<int64_t>()), stages,
                          share(row["successes"].get<int64_t>()),
                          std::to_string(row["simulator_faults"].get<int64_t>())});
  }
  table.note =
      "Simulator faults are episodes whose physics blew up (physics_blow_up): every success rate counts them as "
      "failures; they are the simulator's, not the policy's.";
  return table;
}

}  // namespace tavis::batch::report

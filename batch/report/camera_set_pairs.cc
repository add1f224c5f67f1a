#include "batch/report/camera_set_pairs.h"

#include <map>
#include <string>
#include <tuple>

#include "batch/report/paired_statistics.h"
#include "scenarios/split.h"

namespace tavis::batch::report {

using Json = nlohmann::ordered_json;

Json CameraSetPairRows(const std::vector<CellEpisodes>& cells) {
  // (task, robot, split, seed) -> camera -> per episode success, in episode order.
  using SeedKey = std::tuple<std::string, std::string, std::string, uint64_t>;
  std::map<SeedKey, std::map<std::string, std::vector<bool>>> outcomes;
  using RowKey = std::tuple<std::string, std::string, std::string, std::string>;
  std::vector<RowKey> order;
  for (const CellEpisodes& cell : cells) {
    const std::string camera = ToString(cell.config.camera);
    const SeedKey seed_key{cell.config.task, cell.config.robot, scenarios::ToString(cell.config.split),
                           cell.config.seed};
    std::vector<bool>& successes = outcomes[seed_key][camera];
    for (const cell::EpisodeRecord& record : cell.episodes) successes.push_back(record.success);
    const RowKey row_key{cell.config.task, cell.config.robot, scenarios::ToString(cell.config.split), camera};
    if (camera == "head" || camera == "fixed") continue;
    bool seen = false;
    for (const RowKey& key : order) seen = seen || key == row_key;
    if (!seen) order.push_back(row_key);
  }
  Json rows = Json::array();
  for (const auto& [task, robot, split, camera] : order) {
    PairedCounts counts;
    for (const auto& [seed_key, cameras] : outcomes) {
      if (std::get<0>(seed_key) != task || std::get<1>(seed_key) != robot || std::get<2>(seed_key) != split) continue;
      const auto head = cameras.find("head");
      const auto set = cameras.find(camera);
      // A pair needs both cells with the same episodes.
      if (head == cameras.end() || set == cameras.end() || head->second.size() != set->second.size()) continue;
      for (std::size_t i = 0; i < head->second.size(); ++i) {
        const bool h = head->second[i], s = set->second[i];
        ++(h && s ? counts.both : h ? counts.first_only : s ? counts.second_only : counts.neither);
      }
    }
    if (counts.pairs() == 0) continue;
    const double n = static_cast<double>(counts.pairs());
    const double head_rate = static_cast<double>(counts.both + counts.first_only) / n;
    const double set_rate = static_cast<double>(counts.both + counts.second_only) / n;
    rows.push_back({{"task", task},
                    {"robot", robot},
                    {"split", split},
                    {"camera", camera},
                    {"pairs", counts.pairs()},
                    {"both", counts.both},
                    {"head_only", counts.first_only},
                    {"set_only", counts.second_only},
                    {"neither", counts.neither},
                    {"head_rate", head_rate},
                    {"set_rate", set_rate},
                    {"difference", head_rate - set_rate},
                    {"mcnemar_p", McNemarExactP(counts.first_only, counts.second_only)}});
  }
  return rows;
}

TextTable CameraSetPairTable(const Json& summary) {
  TextTable table{"paired_camera_sets",
                  "Camera sets vs head on matched episodes",
                  {"policy", "task", "robot", "split", "camera set", "pairs", "head %", "set %", "both", "head only",
                   "set only", "neither", "McNemar p"},
                  {},
                  ""};
  for (const Json& row : summary["paired_camera_sets"]) {
    table.rows.push_back({row["label"], row["task"], row["robot"], row["split"], row["camera"],
                          std::to_string(row["pairs"].get<int64_t>()), Percent(row["head_rate"]),
                          Percent(row["set_rate"]), std::to_string(row["both"].get<int64_t>()),
                          std::to_string(row["head_only"].get<int64_t>()),
                          std::to_string(row["set_only"].get<int64_t>()), std::to_string(row["neither"].get<int64_t>()),
                          PValue(row["mcnemar_p"])});
  }
  table.note =
      "Episode i has the same scene under every camera set, so the episodes pair with the head cell's: McNemar's "
      "exact two-sided test on the discordant pairs. head-only: wrist images black; wrists-only: head image black "
      "(the head still moves); fixed-only: the fixed camera, wrist images black.";
  return table;
}

}  // namespace tavis::batch::report

#include "batch/report/perturbation_pairs.h"

#include <map>
#include <string>
#include <tuple>

#include "batch/perturb/perturbation_catalog.h"
#include "batch/report/paired_statistics.h"
#include "scenarios/split.h"

namespace tavis::batch::report {

using Json = nlohmann::ordered_json;

namespace {

std::string Joined(const std::vector<std::string>& choices) {
  std::string text;
  for (const std::string& choice : choices) text += (text.empty() ? "" : "+") + choice;
  return text;
}

}  // namespace

Json PerturbationPairRows(const std::vector<CellEpisodes>& cells) {
  // (base label, task, robot, split, camera) -> perturbation ("" for the base) -> seed -> successes.
  using RowKey = std::tuple<std::string, std::string, std::string, std::string, std::string>;
  std::map<RowKey, std::map<std::string, std::map<uint64_t, std::vector<bool>>>> outcomes;
  std::vector<std::pair<RowKey, std::string>> order;  // perturbed rows in cell order
  for (const CellEpisodes& cell : cells) {
    const std::string label = cell.label.empty() ? cell.config.policy : cell.label;
    const std::string suffix = perturb::PerturbationLabelSuffix(cell.config.perturbations);
    // A sweep's perturbed label is the base label and the suffix; an eval cell's is its policy.
    const bool suffixed = !suffix.empty() && label.size() > suffix.size() &&
                          label.compare(label.size() - suffix.size(), suffix.size(), suffix) == 0;
    const std::string base_label = suffixed ? label.substr(0, label.size() - suffix.size()) : label;
    const RowKey key{base_label, cell.config.task, cell.config.robot, scenarios::ToString(cell.config.split),
                     ToString(cell.config.camera)};
    const std::string perturbation = Joined(cell.config.perturbations);
    std::vector<bool>& successes = outcomes[key][perturbation][cell.config.seed];
    for (const cell::EpisodeRecord& record : cell.episodes) successes.push_back(record.success);
    if (perturbation.empty()) continue;
    bool seen = false;
    for (const auto& row : order) seen = seen || (row.first == key && row.second == perturbation);
    if (!seen) order.emplace_back(key, perturbation);
  }
  Json rows = Json::array();
  for (const auto& [key, perturbation] : order) {
    const auto& by_perturbation = outcomes[key];
    const auto base = by_perturbation.find("");
    if (base == by_perturbation.end()) continue;
    PairedCounts counts;
    for (const auto& [seed, perturbed] : by_perturbation.at(perturbation)) {
      const auto base_seed = base->second.find(seed);
      // A pair needs both cells with the same episodes.
      if (base_seed == base->second.end() || base_seed->second.size() != perturbed.size()) continue;
      for (std::size_t i = 0; i < perturbed.size(); ++i) {
        const bool b = base_seed->second[i], p = perturbed[i];
        ++(b && p ? counts.both : b ? counts.first_only : p ? counts.second_only : counts.neither);
      }
    }
    if (counts.pairs() == 0) continue;
    const double n = static_cast<double>(counts.pairs());
    const double base_rate = static_cast<double>(counts.both + counts.first_only) / n;
    const double perturbed_rate = static_cast<double>(counts.both + counts.second_only) / n;
    const auto& [label, task, robot, split, camera] = key;
    rows.push_back({{"label", label},
                    {"perturbation", perturbation},
                    {"task", task},
                    {"robot", robot},
                    {"split", split},
                    {"camera", camera},
                    {"pairs", counts.pairs()},
                    {"both", counts.both},
                    {"base_only", counts.first_only},
                    {"perturbed_only", counts.second_only},
                    {"neither", counts.neither},
                    {"base_rate", base_rate},
                    {"perturbed_rate", perturbed_rate},
                    {"difference", perturbed_rate - base_rate},
                    {"mcnemar_p", McNemarExactP(counts.first_only, counts.second_only)}});
  }
  return rows;
}

TextTable PerturbationPairTable(const Json& summary) {
  TextTable table{"paired_perturbations",
                  "Perturbations vs the base scene on matched episodes",
                  {"policy", "perturbation", "task", "robot", "split", "camera", "pairs", "base %", "perturbed %",
                   "both", "base only", "perturbed only", "neither", "McNemar p"},
                  {},
                  ""};
  for (const Json& row : summary["paired_perturbations"]) {
    table.rows.push_back({row["label"], row["perturbation"], row["task"], row["robot"], row["split"], row["camera"],
                          std::to_string(row["pairs"].get<int64_t>()), Percent(row["base_rate"]),
                          Percent(row["perturbed_rate"]), std::to_string(row["both"].get<int64_t>()),
                          std::to_string(row["base_only"].get<int64_t>()),
                          std::to_string(row["perturbed_only"].get<int64_t>()),
                          std::to_string(row["neither"].get<int64_t>()), PValue(row["mcnemar_p"])});
  }
  table.note =
      "Episode i keeps its base scene under every perturbation (docs/perturbations.md), so the episodes pair with "
      "the base cell's: McNemar's exact two-sided test on the discordant pairs.";
  return table;
}

}  // namespace tavis::batch::report

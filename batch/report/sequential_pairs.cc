#include "batch/report/sequential_pairs.h"

#include <algorithm>
#include <numeric>

#include "batch/perturb/perturbation_catalog.h"

namespace tavis::batch::report {
namespace {

using Json = nlohmann::ordered_json;

// The label without the perturbation suffix a sweep gives a perturbed cell.
std::string BaseLabel(const PairingCell& cell) {
  const std::string suffix = perturb::PerturbationLabelSuffix(cell.config->perturbations);
  const std::string& label = cell.label;
  const bool suffixed = !suffix.empty() && label.size() > suffix.size() &&
                        label.compare(label.size() - suffix.size(), suffix.size(), suffix) == 0;
  return suffixed ? label.substr(0, label.size() - suffix.size()) : label;
}

// Same task, robot, split and seed: episode i is the same scene.
bool SameScenes(const cell::EvaluationCellConfig& a, const cell::EvaluationCellConfig& b) {
  return a.task == b.task && a.robot == b.robot && a.split == b.split && a.seed == b.seed &&
         a.episode_start == b.episode_start;
}

std::size_t Root(std::vector<std::size_t>& parent, std::size_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

Json SequentialSettingsJson(const SequentialSettings& settings) {
  if (!settings.enabled) return nullptr;
  Json pairs = Json::array();
  if (settings.cameras) pairs.push_back("cameras");
  if (settings.perturbations) pairs.push_back("perturbations");
  Json policies = Json::array();
  for (const auto& [first, second] : settings.policies) policies.push_back({first, second});
  return {{"alpha", settings.test.alpha}, {"block", settings.test.block}, {"pairs", pairs}, {"policies", policies}};
}

SequentialSettings SequentialSettingsFromJson(const Json& json) {
  SequentialSettings settings;
  if (!json.is_object()) return settings;
  settings.enabled = true;
  settings.test.alpha = json.at("alpha").get<double>();
  settings.test.block = json.at("block").get<int>();
  const Json& pairs = json.at("pairs");
  settings.cameras = std::find(pairs.begin(), pairs.end(), "cameras") != pairs.end();
  settings.perturbations = std::find(pairs.begin(), pairs.end(), "perturbations") != pairs.end();
  for (const Json& pair : json.at("policies")) settings.policies.emplace_back(pair.at(0), pair.at(1));
  return settings;
}

std::vector<SequentialPair> SequentialPairs(const std::vector<PairingCell>& cells, const SequentialSettings& settings) {
  std::vector<SequentialPair> pairs;
  if (!settings.enabled) return pairs;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const cell::EvaluationCellConfig& a = *cells[i].config;
    for (std::size_t j = 0; j < cells.size(); ++j) {
      const cell::EvaluationCellConfig& b = *cells[j].config;
      if (i == j || !SameScenes(a, b)) continue;
      if (settings.cameras && cells[i].label == cells[j].label && a.camera == CameraProtocol::kHead &&
          b.camera != CameraProtocol::kHead) {
        pairs.push_back({"camera", i, j});
      }
      const bool same_camera = a.camera == b.camera;
      if (settings.perturbations && same_camera && a.perturbations.empty() && !b.perturbations.empty() &&
          BaseLabel(cells[i]) == BaseLabel(cells[j])) {
        pairs.push_back({"perturbation", i, j});
      }
      for (const auto& [first, second] : settings.policies) {
        if (same_camera && a.perturbations == b.perturbations && BaseLabel(cells[i]) == first &&
            BaseLabel(cells[j]) == second) {
          pairs.push_back({"policy", i, j});
        }
      }
    }
  }
  return pairs;
}

std::vector<std::vector<std::size_t>> SequentialGroups(std::size_t cell_count,
                                                       const std::vector<SequentialPair>& pairs) {
  std::vector<std::size_t> parent(cell_count);
  std::iota(parent.begin(), parent.end(), std::size_t{0});
  std::vector<bool> paired(cell_count, false);
  for (const SequentialPair& pair : pairs) {
    parent[Root(parent, pair.second)] = Root(parent, pair.first);
    paired[pair.first] = paired[pair.second] = true;
  }
  std::vector<std::vector<std::size_t>> groups;
  std::vector<std::size_t> group_of_root(cell_count, cell_count);
  for (std::size_t i = 0; i < cell_count; ++i) {
    if (!paired[i]) continue;
    const std::size_t root = Root(parent, i);
    if (group_of_root[root] == cell_count) {
      group_of_root[root] = groups.size();
      groups.emplace_back();
    }
    groups[group_of_root[root]].push_back(i);
  }
  return groups;
}

bool EveryPairDecided(const std::vector<std::pair<const Outcomes*, const Outcomes*>>& pairs,
                      const SequentialTestSettings& settings) {
  return std::all_of(pairs.begin(), pairs.end(), [&settings](const auto& pair) {
    return DecideSequentially(*pair.first, *pair.second, settings).outcome != SequentialOutcome::kUndecided;
  });
}

}  // namespace tavis::batch::report

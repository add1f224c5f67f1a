#include "batch/sweep/policy_spec.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <stdexcept>
#include <type_traits>
#include <variant>

#include "batch/action_csv.h"
#include "batch/builtin_policies.h"
#include "batch/policy_kinds.h"
#include "batch/remote/observation_keys.h"
#include "batch/sweep/spec_lists.h"
#include "configs/input_file.h"

namespace tavis::batch::sweep {
namespace {

using configs::YamlValue;

template <typename T>
bool Allows(const std::vector<T>& allowed, const T& value) {
  return allowed.empty() || std::find(allowed.begin(), allowed.end(), value) != allowed.end();
}

void ReadCellFilter(const YamlValue& cells, const std::vector<std::string>& known_robots, PolicySpec& policy) {
  RejectUnknownKeys(cells, {"suites", "tasks", "robots", "splits", "cameras"});
  policy.tasks = ReadTasks(cells.Optional("suites"), cells.Optional("tasks"));
  if (const auto robots = cells.Optional("robots")) policy.robots = ReadRobots(*robots, known_robots);
  if (const auto splits = cells.Optional("splits")) policy.splits = ReadSplits(*splits);
  if (const auto cameras = cells.Optional("cameras")) policy.cameras = ReadCameras(*cameras);
  cells.ExpectNoOtherKeys();
}

// The key a setting has in a spec's policy entry.
std::string SpecKey(const char* setting) { return cell::CellSettingNamed(setting).spec_key; }

// A spec's value of a setting, read as the setting's type allows; the error names the key.
void ReadSpecSetting(const YamlValue& value, const cell::CellSetting& setting, cell::EvaluationCellConfig& settings) {
  std::visit(
      [&](auto member) {
        using T = std::decay_t<decltype(settings.*member)>;
        if constexpr (std::is_same_v<T, std::string>) {
          settings.*member = value.AsString();
        } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
          settings.*member = value.AsStrings();
        } else if constexpr (std::is_same_v<T, int>) {
          settings.*member = ReadSettingCount(value, setting.key);
        } else if constexpr (std::is_same_v<T, double>) {
          settings.*member = value.AsDouble({setting.range->low, setting.range->high, false, setting.range->unit});
        } else if constexpr (std::is_enum_v<T>) {
          try {
            settings.*member = cell::SettingText<T>::Read(value.AsString());
          } catch (const std::invalid_argument& error) {
            value.Fail(error.what());
          }
        } else {
          value.Fail("cannot be given in a sweep spec");  // no such setting has a spec key
        }
      },
      setting.member);
}

// What the policy needs and what applies to it only: an error names the spec's key.
void CheckPolicyOptions(const YamlValue& node, const cell::EvaluationCellConfig& settings) {
  const std::string& name = settings.policy;
  if (!IsPolicy(name, PolicyKind::kOpenpi)) {
    try {
      CheckBuiltinPolicyName(name);
    } catch (const std::invalid_argument&) {
      node.Required(SpecKey("policy")).Fail("unknown policy '" + name + "' (known: " + cell::CellPolicyNames() + ")");
    }
  }
  if (IsPolicy(name, PolicyKind::kReplay) && settings.actions_file.empty())
    node.Fail("policy 'replay' needs " + SpecKey("actions_file") + ": FILE.csv");
  if (IsPolicy(name, PolicyKind::kOpenpi) && settings.servers.empty())
    node.Fail("policy 'openpi' needs " + SpecKey("servers") + ": [ws://HOST:PORT, ...]");
  for (const cell::CellSetting& setting : cell::CellSettings()) {
    if (setting.spec_key == nullptr || !node.Optional(setting.spec_key) || cell::SettingApplies(setting.scope, name))
      continue;
    node.Required(setting.spec_key)
        .Fail(std::string("applies to policy '") + cell::ScopePolicyName(setting.scope) + "' only, got policy '" +
              name + "'");
  }
}

// The files a policy names, read as its cells will read them; an error names the spec's key.
void CheckPolicyFiles(const YamlValue& node, const cell::EvaluationCellConfig& settings,
                      const std::string& config_dir) {
  if (!settings.actions_file.empty()) {
    try {
      ReadActionCsv(settings.actions_file);
    } catch (const std::exception& error) {
      node.Required(SpecKey("actions_file")).Fail(error.what());
    }
  }
  if (settings.observation_keys_given) {
    try {
      remote::LoadObservationKeys(settings.observation_keys, config_dir);
    } catch (const std::exception& error) {
      node.Required(SpecKey("observation_keys")).Fail(error.what());
    }
  }
  const std::string& dataset = settings.observation_dataset;
  if (!dataset.empty()) {
    const std::filesystem::path info = std::filesystem::path(dataset) / "meta" / "info.json";
    const std::string not_a_file = configs::WhyNotARegularFile(info);
    if (!not_a_file.empty()) {
      node.Required(SpecKey("observation_dataset"))
          .Fail("'" + dataset + "' is not a LeRobot dataset: " + info.string() + ": " + not_a_file);
    }
  }
}

}  // namespace

bool IsValidLabel(const std::string& label) {
  return !label.empty() && label.size() <= 64 && std::all_of(label.begin(), label.end(), [](unsigned char c) {
    return std::isalnum(c) != 0 || c == '-' || c == '.';
  });
}

PolicySpec ReadPolicySpec(const YamlValue& node, bool label_required, const std::vector<std::string>& known_robots,
                          const std::string& config_dir, PolicyFiles files) {
  PolicySpec policy;
  std::vector<std::string> known_keys;
  for (const cell::CellSetting& setting : cell::CellSettings()) {
    if (setting.spec_key != nullptr) known_keys.push_back(setting.spec_key);
  }
  known_keys.insert(known_keys.end(), {"label", "seed_group", "cells"});
  RejectUnknownKeys(node, known_keys);  // before a typo'd "nmae" reads as a missing name
  node.Required(SpecKey("policy"));     // every entry names its policy
  for (const cell::CellSetting& setting : cell::CellSettings()) {
    if (setting.spec_key == nullptr) continue;
    if (const auto value = node.Optional(setting.spec_key)) ReadSpecSetting(*value, setting, policy.settings);
  }
  policy.settings.observation_keys_given = node.Optional(SpecKey("observation_keys")).has_value();
  if (const auto label = node.Optional("label")) {
    policy.label = label->AsString();
  } else if (label_required) {
    node.Fail("needs label: NAME (each policy of policies: is named by its label)");
  } else {
    policy.label = policy.settings.policy;
  }
  if (!IsValidLabel(policy.label)) {
    node.Required("label").Fail("must be 1 to 64 letters, digits, '-' or '.', got '" + policy.label + "'");
  }
  if (const auto group = node.Optional("seed_group")) {
    policy.seed_group = group->AsString();
    if (!IsValidLabel(policy.seed_group))
      group->Fail("must be 1 to 64 letters, digits, '-' or '.', got '" + policy.seed_group + "'");
  }
  if (const auto cells = node.Optional("cells")) ReadCellFilter(*cells, known_robots, policy);
  node.ExpectNoOtherKeys();
  CheckPolicyOptions(node, policy.settings);
  if (files == PolicyFiles::kRead) CheckPolicyFiles(node, policy.settings, config_dir);
  return policy;
}

bool PolicySpec::Serves(const cell::EvaluationCellConfig& cell) const {
  return Allows(tasks, cell.task) && Allows(robots, cell.robot) && Allows(splits, cell.split) &&
         Allows(cameras, cell.camera);
}

void PolicySpec::ApplyTo(cell::EvaluationCellConfig& cell) const {
  for (const cell::CellSetting& setting : cell::CellSettings()) {
    if (setting.spec_key != nullptr) cell::CopySetting(setting, settings, cell);
  }
  cell.observation_keys_given = settings.observation_keys_given;
}

nlohmann::ordered_json PolicySpecJson(const PolicySpec& policy) {
  nlohmann::ordered_json splits = nlohmann::ordered_json::array();
  for (const scenarios::Split split : policy.splits) splits.push_back(scenarios::ToString(split));
  nlohmann::ordered_json cameras = nlohmann::ordered_json::array();
  for (const CameraProtocol camera : policy.cameras) cameras.push_back(ToString(camera));
  nlohmann::ordered_json json = {{"label", policy.label}, {"seed_group", policy.seed_group}};
  for (const cell::CellSetting& setting : cell::CellSettings()) {
    if (setting.in_manifest)
      json[setting.spec_key] = nlohmann::ordered_json(cell::SettingJson(setting, policy.settings));
  }
  json["cells"] = {{"tasks", policy.tasks}, {"robots", policy.robots}, {"splits", splits}, {"cameras", cameras}};
  return json;
}

}  // namespace tavis::batch::sweep

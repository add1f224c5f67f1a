#include "batch/sweep/policy_spec.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <stdexcept>

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
  policy.tasks = ReadTasks(cells.Optional("suites"), cells.Optional("tasks"));
  if (const auto robots = cells.Optional("robots")) policy.robots = ReadRobots(*robots, known_robots);
  if (const auto splits = cells.Optional("splits")) policy.splits = ReadSplits(*splits);
  if (const auto cameras = cells.Optional("cameras")) policy.cameras = ReadCameras(*cameras);
  cells.ExpectNoOtherKeys();
}

// The files a policy names, read as its cells will read them; an error names the spec's key.
void CheckPolicyFiles(const YamlValue& node, const PolicySpec& policy, const std::string& config_dir) {
  if (!policy.actions_file.empty()) {
    try {
      ReadActionCsv(policy.actions_file);
    } catch (const std::exception& error) {
      node.Required("actions").Fail(error.what());
    }
  }
  if (policy.observation_keys_given) {
    try {
      remote::LoadObservationKeys(policy.observation_keys, config_dir);
    } catch (const std::exception& error) {
      node.Required("keys").Fail(error.what());
    }
  }
  if (!policy.match_dataset.empty()) {
    const std::filesystem::path info = std::filesystem::path(policy.match_dataset) / "meta" / "info.json";
    const std::string not_a_file = configs::WhyNotARegularFile(info);
    if (!not_a_file.empty()) {
      node.Required("match_dataset")
          .Fail("'" + policy.match_dataset + "' is not a LeRobot dataset: " + info.string() + ": " + not_a_file);
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
  policy.name = node.String("name");
  if (const auto label = node.Optional("label")) {
    policy.label = label->AsString();
  } else if (label_required) {
    node.Fail("needs label: NAME (each policy of policies: is named by its label)");
  } else {
    policy.label = policy.name;
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
  if (const auto actions = node.Optional("actions")) policy.actions_file = actions->AsString();
  if (const auto servers = node.Optional("servers")) policy.servers = servers->AsStrings();
  if (const auto keys = node.Optional("keys")) {
    policy.observation_keys = keys->AsString();
    policy.observation_keys_given = true;
  }
  if (const auto dataset = node.Optional("match_dataset")) policy.match_dataset = dataset->AsString();
  if (const auto serving = node.Optional("serving")) {
    try {
      policy.serving = remote::ParseServingMode(serving->AsString());
    } catch (const std::invalid_argument& error) {
      serving->Fail(error.what());
    }
  }
  if (const auto replan = node.Optional("replan_steps")) policy.replan_steps = ReadCount(*replan, 0, 1000000);
  if (const auto timeout = node.Optional("server_timeout_s")) {
    policy.server_timeout_s = timeout->AsDouble({0.001, 86400.0, false, "s"});
  }
  node.ExpectNoOtherKeys();
  const bool served = IsPolicy(policy.name, PolicyKind::kOpenpi);
  if (!served) {
    try {
      CheckBuiltinPolicyName(policy.name);
    } catch (const std::invalid_argument&) {
      node.Required("name").Fail("unknown policy '" + policy.name + "' (known: " + cell::CellPolicyNames() + ")");
    }
  }
  if (IsPolicy(policy.name, PolicyKind::kReplay) && policy.actions_file.empty())
    node.Fail("policy 'replay' needs actions: FILE.csv");
  if (!IsPolicy(policy.name, PolicyKind::kReplay) && !policy.actions_file.empty()) {
    node.Required("actions").Fail("applies to policy 'replay' only, got policy '" + policy.name + "'");
  }
  if (served && policy.servers.empty()) node.Fail("policy 'openpi' needs servers: [ws://HOST:PORT, ...]");
  if (!served && !policy.servers.empty())
    node.Required("servers").Fail("applies to policy 'openpi' only, got policy '" + policy.name + "'");
  for (const char* key : {"keys", "replan_steps", "server_timeout_s", "match_dataset", "serving"}) {
    if (!served && node.Optional(key))
      node.Required(key).Fail("applies to policy 'openpi' only, got policy '" + policy.name + "'");
  }
  if (files == PolicyFiles::kRead) CheckPolicyFiles(node, policy, config_dir);
  return policy;
}

bool PolicySpec::Serves(const cell::EvaluationCellConfig& cell) const {
  return Allows(tasks, cell.task) && Allows(robots, cell.robot) && Allows(splits, cell.split) &&
         Allows(cameras, cell.camera);
}

void PolicySpec::ApplyTo(cell::EvaluationCellConfig& cell) const {
  cell.policy = name;
  cell.actions_file = actions_file;
  cell.servers = servers;
  cell.replan_steps = replan_steps;
  cell.observation_keys = observation_keys;
  cell.observation_keys_given = observation_keys_given;
  cell.observation_dataset = match_dataset;
  cell.serving = serving;
  cell.server_ready_timeout_s = server_timeout_s;
}

nlohmann::ordered_json PolicySpecJson(const PolicySpec& policy) {
  nlohmann::ordered_json splits = nlohmann::ordered_json::array();
  for (const scenarios::Split split : policy.splits) splits.push_back(scenarios::ToString(split));
  nlohmann::ordered_json cameras = nlohmann::ordered_json::array();
  for (const CameraProtocol camera : policy.cameras) cameras.push_back(ToString(camera));
  return {{"label", policy.label},
          {"seed_group", policy.seed_group},
          {"name", policy.name},
          {"actions", policy.actions_file},
          {"servers", policy.servers},
          {"keys", policy.observation_keys},
          {"replan_steps", policy.replan_steps},
          {"match_dataset", policy.match_dataset},
          {"serving", remote::ToString(policy.serving)},
          {"cells", {{"tasks", policy.tasks}, {"robots", policy.robots}, {"splits", splits}, {"cameras", cameras}}}};
}

}  // namespace tavis::batch::sweep

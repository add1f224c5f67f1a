#include "batch/sweep/sweep_spec.h"

#include <algorithm>
#include <cctype>
#include <limits>
#include <stdexcept>

#include "batch/builtin_policies.h"
#include "configs/robot_config.h"
#include "configs/yaml_reader.h"
#include "scenarios/registry.h"

namespace tavis::batch::sweep {
namespace {

using configs::YamlValue;

std::string Join(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : ", ") + name;
  return text;
}

// A non-empty list of strings without repeats; each passed to `check`, which throws
// std::invalid_argument for a bad one (its message becomes the error's).
template <typename Check>
std::vector<std::string> ReadNames(const YamlValue& list, Check check) {
  const std::vector<YamlValue> elements = list.Elements();
  if (elements.empty()) list.Fail("must name at least one, got []");
  std::vector<std::string> names;
  for (const YamlValue& element : elements) {
    const std::string name = element.AsString();
    try {
      check(name);
    } catch (const std::invalid_argument& error) {
      element.Fail(error.what());
    }
    if (std::find(names.begin(), names.end(), name) != names.end()) element.Fail("'" + name + "' is listed twice");
    names.push_back(name);
  }
  return names;
}

int ReadCount(const YamlValue& value, int low, int high) {
  int count = 0;
  try {
    count = value.AsInt();
  } catch (const configs::ConfigError&) {
    value.Fail("must be an integer from " + std::to_string(low) + " to " + std::to_string(high) + ", got " + value.Text());
  }
  if (count < low || count > high) {
    value.Fail("must be an integer from " + std::to_string(low) + " to " + std::to_string(high) + ", got " + value.Text());
  }
  return count;
}

uint64_t ReadSeed(const YamlValue& value) {
  const std::string text = value.AsString();
  const bool digits = !text.empty() && text.size() <= 20 &&
                      std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isdigit(c) != 0; });
  if (!digits || (text.size() == 20 && text > "18446744073709551615")) {
    value.Fail("must be an integer from 0 to 18446744073709551615, got " + value.Text());
  }
  return std::stoull(text);
}

void ReadPolicy(const YamlValue& policy, SweepSpec& spec) {
  spec.policy = policy.String("name");
  if (const auto actions = policy.Optional("actions")) spec.actions_file = actions->AsString();
  if (const auto servers = policy.Optional("servers")) spec.servers = servers->AsStrings();
  if (const auto keys = policy.Optional("keys")) spec.observation_keys = keys->AsString();
  if (const auto replan = policy.Optional("replan_steps")) spec.replan_steps = ReadCount(*replan, 0, 1000000);
  if (const auto timeout = policy.Optional("server_timeout_s")) {
    spec.server_timeout_s = timeout->AsDouble({0.001, 86400.0, false, "s"});
  }
  policy.ExpectNoOtherKeys();
  const bool served = spec.policy == "openpi";
  if (!served) {
    try {
      CheckBuiltinPolicyName(spec.policy);
    } catch (const std::invalid_argument&) {
      policy.Required("name").Fail("unknown policy '" + spec.policy + "' (known: " + CellPolicyNames() + ")");
    }
  }
  if (spec.policy == "replay" && spec.actions_file.empty()) policy.Fail("policy 'replay' needs actions: FILE.csv");
  if (spec.policy != "replay" && !spec.actions_file.empty()) {
    policy.Required("actions").Fail("applies to policy 'replay' only, got policy '" + spec.policy + "'");
  }
  if (served && spec.servers.empty()) policy.Fail("policy 'openpi' needs servers: [ws://HOST:PORT, ...]");
  if (!served && !spec.servers.empty()) policy.Required("servers").Fail("applies to policy 'openpi' only, got policy '" + spec.policy + "'");
  for (const char* key : {"keys", "replan_steps", "server_timeout_s"}) {
    if (!served && policy.Optional(key)) policy.Required(key).Fail("applies to policy 'openpi' only, got policy '" + spec.policy + "'");
  }
}

SweepSpec ReadSpec(const YamlValue& root, const std::string& source, const std::string& config_dir) {
  SweepSpec spec;
  spec.source = source;
  const auto suites = root.Optional("suites");
  const auto tasks = root.Optional("tasks");
  if (!suites && !tasks) root.Fail("needs suites: [...] or tasks: [...] (or both)");
  if (suites) {
    spec.suites = ReadNames(*suites, [](const std::string& name) { scenarios::ParseSuite(name); });
    for (const std::string& suite : spec.suites) {
      for (const scenarios::ScenarioDef* scenario : scenarios::SuiteScenarios(scenarios::ParseSuite(suite))) {
        spec.tasks.push_back(scenario->name);
      }
    }
  }
  if (tasks) {
    for (const std::string& task : ReadNames(*tasks, [](const std::string& name) { scenarios::FindScenario(name); })) {
      if (std::find(spec.tasks.begin(), spec.tasks.end(), task) == spec.tasks.end()) spec.tasks.push_back(task);
    }
  }
  const std::vector<std::string> known_robots = configs::KnownRobots(config_dir);
  spec.robots = ReadNames(root.Required("robots"), [&known_robots](const std::string& name) {
    if (std::find(known_robots.begin(), known_robots.end(), name) == known_robots.end()) {
      throw std::invalid_argument("unknown robot '" + name + "' (known: " + Join(known_robots) + ")");
    }
  });
  for (const std::string& split : ReadNames(root.Required("splits"), [](const std::string& name) { scenarios::ParseSplit(name); })) {
    spec.splits.push_back(scenarios::ParseSplit(split));
  }
  for (const std::string& camera : ReadNames(root.Required("cameras"), [](const std::string& name) { ParseCameraProtocol(name); })) {
    spec.cameras.push_back(ParseCameraProtocol(camera));
  }
  const YamlValue seeds = root.Required("seeds");
  if (seeds.Elements().empty()) seeds.Fail("must name at least one, got []");
  for (const YamlValue& seed : seeds.Elements()) {
    const uint64_t value = ReadSeed(seed);
    if (std::find(spec.seeds.begin(), spec.seeds.end(), value) != spec.seeds.end()) seed.Fail(seed.Text() + " is listed twice");
    spec.seeds.push_back(value);
  }
  spec.episodes = ReadCount(root.Required("episodes"), 1, 100000000);
  if (const auto envs = root.Optional("envs")) spec.envs = ReadCount(*envs, 1, 4096);
  ReadPolicy(root.Required("policy"), spec);
  root.ExpectNoOtherKeys();
  return spec;
}

}  // namespace

SweepSpec ParseSweepSpec(const std::string& yaml_text, const std::string& source_name, const std::string& config_dir) {
  return ReadSpec(YamlValue::LoadString(yaml_text, source_name), source_name, config_dir);
}

SweepSpec LoadSweepSpec(const std::string& path, const std::string& config_dir) {
  return ReadSpec(YamlValue::LoadFile(path), path, config_dir);
}

nlohmann::ordered_json SweepSpecJson(const SweepSpec& spec) {
  nlohmann::ordered_json splits = nlohmann::ordered_json::array();
  for (const scenarios::Split split : spec.splits) splits.push_back(scenarios::ToString(split));
  nlohmann::ordered_json cameras = nlohmann::ordered_json::array();
  for (const CameraProtocol camera : spec.cameras) cameras.push_back(ToString(camera));
  return {{"suites", spec.suites},
          {"tasks", spec.tasks},
          {"robots", spec.robots},
          {"splits", splits},
          {"cameras", cameras},
          {"seeds", spec.seeds},
          {"episodes", spec.episodes},
          {"policy",
           {{"name", spec.policy},
            {"actions", spec.actions_file},
            {"servers", spec.servers},
            {"keys", spec.observation_keys},
            {"replan_steps", spec.replan_steps}}}};
}

std::vector<SweepCell> ExpandCells(const SweepSpec& spec, const std::string& config_dir) {
  std::vector<SweepCell> cells;
  for (const std::string& task : spec.tasks) {
    for (const std::string& robot : spec.robots) {
      for (const scenarios::Split split : spec.splits) {
        for (const CameraProtocol camera : spec.cameras) {
          for (const uint64_t seed : spec.seeds) {
            SweepCell cell;
            EvaluationCellConfig& config = cell.config;
            config.task = task;
            config.robot = robot;
            config.split = split;
            config.camera = camera;
            config.seed = seed;
            config.policy = spec.policy;
            config.actions_file = spec.actions_file;
            config.servers = spec.servers;
            config.replan_steps = spec.replan_steps;
            config.observation_keys = spec.observation_keys;
            config.server_ready_timeout_s = spec.server_timeout_s;
            config.episodes = spec.episodes;
            config.envs = spec.envs;
            config.config_dir = config_dir;
            cell.id = task + "_" + robot + "_" + scenarios::ToString(split) + "_" + ToString(camera) + "_" + spec.policy +
                      "_s" + std::to_string(seed);
            cells.push_back(std::move(cell));
          }
        }
      }
    }
  }
  return cells;
}

Shard ParseShard(const std::string& text) {
  const std::size_t slash = text.find('/');
  const auto number = [&text](const std::string& part) {
    if (part.empty() || part.size() > 6 || !std::all_of(part.begin(), part.end(), [](unsigned char c) { return std::isdigit(c) != 0; })) {
      throw std::invalid_argument("--shard must be I/N with 0 <= I < N (e.g. 0/3), got '" + text + "'");
    }
    return std::stoi(part);
  };
  if (slash == std::string::npos) number("");
  const Shard shard{number(text.substr(0, slash)), number(text.substr(slash + 1))};
  if (shard.count < 1 || shard.index >= shard.count) {
    throw std::invalid_argument("--shard must be I/N with 0 <= I < N (e.g. 0/3), got '" + text + "'");
  }
  return shard;
}

bool InShard(std::size_t cell_position, const Shard& shard) {
  return cell_position % static_cast<std::size_t>(shard.count) == static_cast<std::size_t>(shard.index);
}

}  // namespace tavis::batch::sweep

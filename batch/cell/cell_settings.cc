#include "batch/cell/cell_settings.h"

#include <cstring>
#include <stdexcept>
#include <type_traits>

#include "batch/output/json_error_text.h"
#include "batch/policy_kinds.h"
#include "batch/remote/observation_keys.h"
#include "batch/scene/scene_settings.h"
#include "kinematics/invariant.h"

namespace tavis::batch::cell {
namespace {

using Config = EvaluationCellConfig;

// The table, in groups (what a cell is, the policy, the served policy, the episodes, what is
// rendered): each entry is one setting's whole declaration, made by the builder of its kind.

// A scene setting's flag and help, declared with the scene (scene_settings.h) and registered by
// every command that runs one.
const char* SceneFlag(const char* key) { return scene::SceneSettingNamed(key).flag; }
const std::string& SceneHelp(const char* key) { return scene::SceneSettingNamed(key).help; }

// A setting that says what the cell is: cell.json and summary.json record it under any policy.
CellSetting Identity(const char* key, SettingMember member) {
  return CellSetting(key, member).Records(Recorded::kAlways, Recorded::kAlways);
}

// A setting of one policy: another must leave it at its default; its help starts "For --policy P:".
CellSetting OfPolicy(SettingScope scope, const char* key, SettingMember member) {
  return CellSetting(key, member).AppliesTo(scope);
}

std::vector<CellSetting> WhatTheCellIs() {
  return {
      Identity("task", &Config::task).Flag(SceneFlag("task"), EvalOption::kByHand, SceneHelp("task")),
      Identity("robot", &Config::robot).Flag(SceneFlag("robot"), EvalOption::kByHand, SceneHelp("robot")),
      Identity("split", &Config::split).Flag(SceneFlag("split"), EvalOption::kByHand, SceneHelp("split")),
      Identity("camera", &Config::camera)
          .Flag("--camera", EvalOption::kShowingDefault,
                "Camera protocol: head (the policy sees and moves the head camera; GALT computed) or fixed\n"
                "(the fixed camera instead, neck actions and neck state zeroed, no GALT); episode i has the\n"
                "same scene under both, so a head and a fixed cell pair. Camera sets: head-only (wrist images\n"
                "black), wrists-only (head rules, the head image black), fixed-only (fixed rules, wrist images\n"
                "black); head is head + wrists, fixed is fixed + wrists; every set pairs with head"),
  };
}

std::vector<CellSetting> ThePolicy() {
  return {
      Identity("policy", &Config::policy)
          .InSpec("name", true)
          .Flag("--policy", EvalOption::kShowingDefault,
                "Policy (" + PolicyNames(/*built_in_only=*/false) +
                    "); openpi: a policy served over openpi's websocket\n"
                    "protocol (--server), acting at 20 Hz on the cameras its --keys name"),
      OfPolicy(SettingScope::kExpert, "expert_mode", &Config::expert_mode)
          .Records(Recorded::kWhereItApplies, Recorded::kWhereItApplies)  // it decides the expert's records
          .Flag(SceneFlag("expert_mode"), EvalOption::kByHand, SceneHelp("expert_mode")),
      OfPolicy(SettingScope::kExpert, "expert_hz", &Config::expert_hz)
          .Records(Recorded::kAlways, Recorded::kAlways)
          .Flag("--expert-hz", EvalOption::kShowingDefault,
                "60 (its action may change every control tick) or 20 (held for three ticks, as\n"
                "a 20 Hz policy acts; each episode's actions are saved as DIR/actions/episode_<i>.csv.gz, which\n"
                "--policy replay --actions DIR/actions plays back exactly)")
          .Choices({60, 20}),
      OfPolicy(SettingScope::kReplay, "actions_file", &Config::actions_file)
          .Records(Recorded::kAlways, Recorded::kAlways)
          .InSpec("actions", true)
          .Flag("--actions", EvalOption::kHidingDefault,
                "T x 19 CSV of canonical actions, one row per 20 Hz step, played in every\n"
                "episode; or a folder of episode_<i>.csv or .csv.gz (a served cell's DIR/actions), episode i playing\n"
                "its own"),
  };
}

std::vector<CellSetting> TheServedPolicy() {
  return {
      OfPolicy(SettingScope::kServed, "servers", &Config::servers)
          .Records(Recorded::kAlways, Recorded::kWhereItApplies)
          .InSpec("servers", true)
          .Flag("--server", EvalOption::kHidingDefault,
                "ws://HOST:PORT of a policy server; repeat it to spread env slots (slot i asks server i mod K)"),
      OfPolicy(SettingScope::kServed, "observation_keys", &Config::observation_keys)
          .Records(Recorded::kAlways, Recorded::kNo)  // summary.json names the layout's source (CellResult)
          .InSpec("keys", true)
          .Flag("--keys", EvalOption::kShowingDefault,
                "the request's key layout, a preset (" + remote::KeyPresetNames() +
                    ") or a\n"
                    "YAML file of that schema (configs/policy_keys/*.yaml: keys per camera, state and prompt,\n"
                    "hwc/chw images, image size, letterbox). tavis: the dataset's keys (observation.images.OBS_HEAD,\n"
                    "..., observation.state, prompt and task) at 320x240 (docs/observation.md)"),
      OfPolicy(SettingScope::kServed, "replan_steps", &Config::replan_steps)
          .Records(Recorded::kAlways, Recorded::kWhereItApplies)
          .InSpec("replan_steps", true)
          .Flag("--replan-steps", EvalOption::kShowingDefault,
                "rows of each action chunk an env steps with before asking again\n"
                "(0: the whole chunk, as openpi's ActionChunkBroker; its LIBERO example uses 5)")
          .Range(0, 1000000),
      OfPolicy(SettingScope::kServed, "observation_dataset", &Config::observation_dataset)
          .Records(Recorded::kAlways, Recorded::kUnlessDefault)
          .InSpec("match_dataset", true)
          .Flag("--match-dataset", EvalOption::kHidingDefault,
                "serve the layout of the LeRobot dataset DIR the policy was trained on (its\n"
                "meta/info.json: image keys, cameras, image size); with --keys or --image-size as well, every way\n"
                "the served layout differs from the dataset's is printed and recorded in summary.json"),
      OfPolicy(SettingScope::kServed, "serving", &Config::serving)
          .Records(Recorded::kNo, Recorded::kWhereItApplies)  // not in cell.json: the records do not depend on it
          .InSpec("serving", true)
          .Flag("--serving", EvalOption::kShowingDefault,
                "serial (one connection per server, requests one at a time in env order),\n"
                "per-env (one connection per env slot, requests of a tick in flight together) or batched (one\n"
                "message per server per tick with every due env stacked; the server's metadata must declare\n"
                "batched_requests: true). Records do not depend on it"),
  };
}

std::vector<CellSetting> TheServersLimits() {
  return {
      OfPolicy(SettingScope::kServed, "server_ready_timeout_s", &Config::server_ready_timeout_s)
          .InSpec("server_timeout_s", false)  // a shard may wait longer for its servers
          .Flag("--server-timeout", EvalOption::kShowingDefault,
                "seconds to wait for each server's /healthz before giving up")
          .Range(0.001, 86400, "s"),
      OfPolicy(SettingScope::kServed, "reply_timeout_s", &Config::reply_timeout_s)
          .Flag("--reply-timeout", EvalOption::kShowingDefault,
                "seconds to wait for each reply before the cell stops (a server's first\n"
                "inference may compile its model)")
          .Range(0.001, 86400, "s"),
      OfPolicy(SettingScope::kServed, "max_reply_mb", &Config::max_reply_mb)
          .Flag("--max-reply-mb", EvalOption::kShowingDefault,
                "the largest reply accepted, in MiB; a longer one ends its episode as\n"
                "invalid_action, read no further (the default holds a 100,000-row float64 chunk)")
          .Range(0.001, 4096, "MiB"),
  };
}

std::vector<CellSetting> TheEpisodes() {
  return {
      CellSetting("episodes", &Config::episodes)
          .Records(Recorded::kAlways, Recorded::kNo)  // summary.json counts the episodes it holds (n_episodes)
          .Flag("--episodes", EvalOption::kShowingDefault, "Episodes in the cell")
          .Range(1, 100000000),
      CellSetting("episode_start", &Config::episode_start)
          .Records(Recorded::kUnlessDefault, Recorded::kNo)  // so cells written before it existed still resume
          .Flag("--episode", EvalOption::kHidingDefault,
                "Run only episode I of the seed: the scene, and with a folder of --actions the actions, it has in\n"
                "the full cell (replaces --episodes; the cell's one record is episode I)")
          .Range(0, 100000000),
      Identity("seed", &Config::seed).Flag(SceneFlag("seed"), EvalOption::kByHand, SceneHelp("seed")),
      CellSetting("envs", &Config::envs)  // summary.json records the slots that ran (CellResult::envs)
          .Flag("--envs", EvalOption::kHidingDefault,
                "Parallel env slots stepped lock-step, for a served policy (default: 32, or 6 per\n"
                "thread when that is more: 96 on 16 threads); a built-in policy runs one slot per thread instead,\n"
                "rendered or not (results do not depend on it)")
          .Range(1, 4096),
      // Each level with its settings (CellSettingsJson).
      CellSetting("perturbations", &Config::perturbations)
          .Records(Recorded::kUnlessDefault, Recorded::kUnlessDefault)
          .Flag(SceneFlag("perturbations"), EvalOption::kByHand, SceneHelp("perturbations")),
  };
}

std::vector<CellSetting> WhatIsRendered() {
  const std::string image_size =
      "Size of the policy's images, WIDTHxHEIGHT (default: the observation keys' size for --policy\n"
      "openpi: 320x240 for tavis, 224x224 for libero and aloha, the dataset's with --match-dataset;\n"
      "otherwise the reference's 640x480)";
  return {
      CellSetting("render_cameras", &Config::render_cameras)
          .Records(Recorded::kAlways, Recorded::kNo)  // summary.json names the cameras rendered (CellResult)
          .Flag("--render-cameras", EvalOption::kByHand,
                "Comma-separated cameras to render on every policy tick (20 Hz) even if the policy uses no\n"
                "images, e.g. head,left_wrist,right_wrist (known: head, fixed, left_wrist, right_wrist); the\n"
                "images are discarded: for measuring throughput with rendering"),
      CellSetting("image_width", &Config::image_width)
          .Records(Recorded::kAlways, Recorded::kNo)  // as given (0: the policy's own); summary.json has it resolved
          .Flag("--image-size", EvalOption::kByHand, image_size),
      CellSetting("image_height", &Config::image_height)
          .Records(Recorded::kAlways, Recorded::kNo)
          .Flag("--image-size", EvalOption::kByHand, image_size),
      CellSetting("config_dir", &Config::config_dir)
          .Records(Recorded::kNo, Recorded::kAlways)  // cell.json records what the files say (its identity) instead
          .Flag("--config-dir", EvalOption::kByHand, "Directory holding robots/*.yaml"),
      CellSetting("profile", &Config::profile)
          .Flag("--profile", EvalOption::kShowingDefault,
                "Time every stage (actions/IK, physics, neck, task, reset, render, policy, recording) and\n"
                "episode; print the shares, the critical path (unlimited threads) and thread-count\n"
                "estimates, and write DIR/profile.json"),
  };
}

template <typename T>
nlohmann::json ValueJson(const T& value) {
  if constexpr (std::is_enum_v<T>) {
    return SettingText<T>::Write(value);
  } else {
    return value;
  }
}

// A recorded value read back as the member's type (an enum from its text); a perturbation level
// may be the object cell.json writes.
template <typename T>
T ValueFromJson(const nlohmann::json& value) {
  if constexpr (std::is_enum_v<T>) {
    return SettingText<T>::Read(value.get<std::string>());
  } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
    std::vector<std::string> items;
    for (const nlohmann::json& item : value) {
      items.push_back(item.is_object() ? item.at("axis").get<std::string>() + ":" + item.at("level").get<std::string>()
                                       : item.get<std::string>());
    }
    return items;
  } else {
    return value.get<T>();
  }
}

}  // namespace

CellSetting& CellSetting::AppliesTo(SettingScope policies) {
  scope = policies;
  return *this;
}

CellSetting& CellSetting::Records(Recorded in_cell, Recorded in_summary_json) {
  in_cell_json = in_cell;
  in_summary = in_summary_json;
  return *this;
}

CellSetting& CellSetting::InSpec(const char* key_in_spec, bool written_in_manifest) {
  spec_key = key_in_spec;
  in_manifest = written_in_manifest;
  return *this;
}

CellSetting& CellSetting::Flag(const char* name, EvalOption how, const std::string& text) {
  flag = name;
  option = how;
  help = scope == SettingScope::kAnyPolicy ? text : "For --policy " + std::string(ScopePolicyName(scope)) + ": " + text;
  return *this;
}

CellSetting& CellSetting::Range(double low, double high, const char* unit) {
  range = output::SettingRange::Between(low, high, unit);
  return *this;
}

CellSetting& CellSetting::Choices(std::vector<double> values) {
  range = output::SettingRange::OneOf(std::move(values));
  return *this;
}

const std::vector<CellSetting>& CellSettings() {
  static const std::vector<CellSetting> settings = [] {
    std::vector<CellSetting> all;
    for (std::vector<CellSetting> group :
         {WhatTheCellIs(), ThePolicy(), TheServedPolicy(), TheServersLimits(), TheEpisodes(), WhatIsRendered()}) {
      all.insert(all.end(), group.begin(), group.end());
    }
    return all;
  }();
  return settings;
}

const CellSetting* FindCellSetting(const std::string& key) {
  for (const CellSetting& setting : CellSettings()) {
    if (key == setting.key) return &setting;
  }
  return nullptr;
}

const CellSetting& CellSettingNamed(const std::string& key) {
  const CellSetting* setting = FindCellSetting(key);
  TAVIS_INVARIANT(setting != nullptr, ("no cell setting is named '" + key + "'").c_str());
  return *setting;
}

const char* ScopePolicyName(SettingScope scope) {
  switch (scope) {
    case SettingScope::kExpert: return PolicyName(PolicyKind::kExpert);
    case SettingScope::kReplay: return PolicyName(PolicyKind::kReplay);
    case SettingScope::kServed: return PolicyName(PolicyKind::kOpenpi);
    case SettingScope::kAnyPolicy: break;
  }
  return "";
}

bool SettingApplies(SettingScope scope, const std::string& policy) {
  return scope == SettingScope::kAnyPolicy || policy == ScopePolicyName(scope);
}

nlohmann::json SettingJson(const CellSetting& setting, const EvaluationCellConfig& config) {
  return std::visit([&config](auto member) { return ValueJson(config.*member); }, setting.member);
}

bool HasDefaultValue(const CellSetting& setting, const EvaluationCellConfig& config) {
  static const EvaluationCellConfig defaults;
  return std::visit([&config](auto member) { return config.*member == defaults.*member; }, setting.member);
}

void CopySetting(const CellSetting& setting, const EvaluationCellConfig& from, EvaluationCellConfig& to) {
  std::visit([&](auto member) { to.*member = from.*member; }, setting.member);
}

nlohmann::json RecordedSettingsJson(const EvaluationCellConfig& config, CellRecord record, bool served) {
  nlohmann::json json = nlohmann::json::object();
  for (const CellSetting& setting : CellSettings()) {
    const Recorded how = record == CellRecord::kCellJson ? setting.in_cell_json : setting.in_summary;
    // A served policy's settings are recorded where the cell was run with one.
    const bool applies = setting.scope == SettingScope::kServed ? served : SettingApplies(setting.scope, config.policy);
    const bool recorded = how == Recorded::kAlways || (how == Recorded::kWhereItApplies && applies) ||
                          (how == Recorded::kUnlessDefault && applies && !HasDefaultValue(setting, config));
    if (recorded) json[setting.key] = SettingJson(setting, config);
  }
  return json;
}

void ReadRecordedSettings(const nlohmann::json& record, EvaluationCellConfig& config) {
  for (const CellSetting& setting : CellSettings()) {
    if (!record.is_object() || !record.contains(setting.key)) continue;
    const nlohmann::json& value = record.at(setting.key);
    try {
      std::visit([&](auto member) { config.*member = ValueFromJson<std::decay_t<decltype(config.*member)>>(value); },
                 setting.member);
    } catch (const std::exception& error) {  // nlohmann's type errors, an unknown enum's text
      throw std::invalid_argument(std::string(setting.key) + ": cannot read " + value.dump() + ": " +
                                  output::JsonErrorText(error.what()));
    }
  }
}

void CheckSettingValues(const EvaluationCellConfig& config) {
  for (const CellSetting& setting : CellSettings()) {
    std::visit(
        [&](auto member) {
          using T = std::decay_t<decltype(config.*member)>;
          if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
            if (setting.range)
              output::CheckSettingRange(setting.key, static_cast<double>(config.*member), *setting.range);
          }
        },
        setting.member);
    if (!SettingApplies(setting.scope, config.policy) && !HasDefaultValue(setting, config)) {
      throw output::SettingError(setting.key, std::string("applies to policy '") + ScopePolicyName(setting.scope) +
                                                  "' only, got policy '" + config.policy + "'");
    }
  }
}

}  // namespace tavis::batch::cell

// An evaluation cell's settings, each declared once: the struct a cell is run from
// (EvaluationCellConfig) and, for every setting a user gives, one entry of the table CellSettings()
// saying its key (as cell.json, summary.json and error messages name it), its key in a sweep
// spec's policy entry, `tavis eval`'s flag and help text, which policies it applies to, where it
// is recorded and the values it may take. The command line (tools/cell_options.*), the sweep spec
// (batch/sweep/policy_spec.*), cell.json and summary.json, the sweep manifest and the checks
// (PlanCell) read this table rather than listing the settings again.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/camera_protocol.h"
#include "batch/output/setting_error.h"
#include "batch/remote/remote_policy.h"
#include "batch/remote/server_contract.h"
#include "scenarios/expert/expert_mode.h"
#include "scenarios/split.h"

namespace tavis::batch::cell {

struct EvaluationCellConfig {
  std::string task = "clutter-pick-cube";
  std::string robot = "gr1t2";
  scenarios::Split split = scenarios::Split::kId;
  CameraProtocol camera = CameraProtocol::kHead;
  std::string policy = "expert";
  // For the scripted expert: how its head leads (gaze-first, or head-still for the fixed-camera
  // bias ablation); another policy must leave it gaze-first.
  scenarios::expert::ExpertMode expert_mode = scenarios::expert::ExpertMode::kGazeFirst;
  std::string actions_file;  // for the replay policy: a CSV, or a folder of episode_<i>.csv
  // For the expert: 60 (its action may change every control tick) or 20 (held for three ticks,
  // as a 20 Hz policy acts; each episode's actions are then saved at 20 Hz for --policy replay).
  int expert_hz = 60;
  // For the served policy "openpi": its policy servers (env slot i asks servers[i % size]) and
  // the chunk rows an env steps with before asking again (0: the whole chunk).
  std::vector<std::string> servers;
  int replan_steps = 0;
  // The request layout: a preset (remote::KeyPresetNames()) or a YAML file (observation_keys.h).
  std::string observation_keys = "tavis";
  // A LeRobot dataset whose meta/info.json gives the layout (keys, cameras, image size) when
  // observation_keys_given is false; when it is true (or an image size is given), a layout that
  // differs from the dataset's is reported (CellPlan::layout_differences), not refused.
  std::string observation_dataset;
  bool observation_keys_given = false;  // not a setting: whether observation_keys was given
  // Not settings: whether replan_steps was given, and the contract the cell's first policy server
  // declared at connect (remote/server_contract.h; ReadDeclaredContract reads it before the cell is
  // planned): the plan adopts its layout and executed steps, or refuses a setting given that
  // contradicts it. nullopt: the server declares none (a plain openpi server), nothing changes.
  bool replan_steps_given = false;
  std::optional<remote::ServerContract> declared_contract;
  // How requests travel (remote_policy.h); the records do not depend on it.
  remote::ServingMode serving = remote::ServingMode::kSerial;
  double server_ready_timeout_s = 60.0;  // per server, for its /healthz to answer before the cell starts
  double reply_timeout_s = 300.0;  // per request, for the reply (a server's first inference may compile its model)
  double max_reply_mb = 16.0;      // a longer reply ends its episode (remote::kDefaultMaxReplyBytes)
  int episodes = 96;
  // The cell's first episode index: it holds episodes episode_start .. episode_start + episodes - 1
  // (`tavis eval --episode I` runs episode I of the seed alone, the scene it has in a full cell).
  int64_t episode_start = 0;
  // Not a setting: episodes before this one are not run (a resumed cell has their records
  // already); in [episode_start, episode_start + episodes] (at the end, nothing runs).
  int64_t first_episode = 0;
  int envs = 32;  // parallel env slots
  uint64_t seed = 0;
  std::string config_dir;  // holds robots/*.yaml
  // Cameras rendered on every policy tick even if the policy does not consume them (throughput
  // runs); the policy's own cameras() are always rendered. Names from SceneCameraNames().
  std::vector<std::string> render_cameras;
  // The size of the policy's images; 0 x 0: the policy's own (a served policy's observation
  // keys, 224 x 224 for the presets; the reference's 640 x 480 otherwise).
  int image_width = 0;
  int image_height = 0;
  // Not a setting: keep every control tick's commanded action in the records (tests compare
  // them); otherwise a cell's memory does not grow with its episodes.
  bool keep_actions = false;
  // Time every stage and episode (CellResult::profile; `tavis eval --profile`).
  bool profile = false;
  // Perturbation levels, "AXIS:LEVEL" each, at most one per axis (batch/perturb/perturbation_catalog.h,
  // docs/perturbations.md); empty: the base scene. Episode i keeps its base scene under every one.
  std::vector<std::string> perturbations;
};

// The policies a setting is for. Under another policy it must keep its default.
enum class SettingScope { kAnyPolicy, kExpert, kReplay, kServed };

// Whether a record (cell.json, summary.json) holds a setting: never, always, only where it
// applies (SettingScope), or only when it is not at its default (so records written before the
// setting existed still compare equal).
enum class Recorded { kNo, kAlways, kWhereItApplies, kUnlessDefault };

// How `tavis eval` takes a setting: not at all, as an option of its own (showing its default in
// --help or not), or by hand in tools/ (another form: --image-size for the two sizes, a comma
// list, --config-dir), with the flag and help text still declared here.
enum class EvalOption { kNone, kShowingDefault, kHidingDefault, kByHand };

template <typename T>
using CellMember = T EvaluationCellConfig::*;
// The member a setting is, with its type; code that reads or writes settings visits it
// (std::visit) and handles each type once.
using SettingMember = std::variant<CellMember<std::string>, CellMember<std::vector<std::string>>, CellMember<int>,
                                   CellMember<int64_t>, CellMember<uint64_t>, CellMember<double>, CellMember<bool>,
                                   CellMember<scenarios::Split>, CellMember<CameraProtocol>,
                                   CellMember<scenarios::expert::ExpertMode>, CellMember<remote::ServingMode>>;

struct CellSetting {
  CellSetting(const char* name, SettingMember of) : key(name), member(of) {}

  const char* key;  // in cell.json and summary.json, and what library errors name
  SettingMember member;
  SettingScope scope = SettingScope::kAnyPolicy;
  Recorded in_cell_json = Recorded::kNo;
  Recorded in_summary = Recorded::kNo;
  const char* spec_key = nullptr;  // its key in a sweep spec's policy entry; null: not there
  bool in_manifest = false;        // written in the sweep manifest's policy (what merge compares)
  const char* flag = nullptr;      // `tavis eval`'s flag
  EvalOption option = EvalOption::kNone;
  std::string help;
  std::optional<output::SettingRange> range;  // numbers: the values allowed

  // Builders for the table's entries.
  CellSetting& AppliesTo(SettingScope policies);
  CellSetting& Records(Recorded in_cell, Recorded in_summary_json);  // how cell.json and summary.json hold it
  CellSetting& InSpec(const char* key_in_spec, bool written_in_manifest);
  // The help of a setting of one policy starts "For --policy P: " (AppliesTo comes first).
  CellSetting& Flag(const char* name, EvalOption how, const std::string& text);
  CellSetting& Range(double low, double high, const char* unit = "");
  CellSetting& Choices(std::vector<double> values);
};

// Every setting, in the order `tavis eval --help` lists them and a sweep manifest writes a
// policy's keys.
const std::vector<CellSetting>& CellSettings();
// The setting with that key, or null.
const CellSetting* FindCellSetting(const std::string& key);
// The setting with that key; a key no setting has is a bug (an invariant aborts).
const CellSetting& CellSettingNamed(const std::string& key);

// The policy a scope names ("expert", "replay", "openpi"); "" for kAnyPolicy.
const char* ScopePolicyName(SettingScope scope);
// True if the setting's scope covers `policy` (a policy name; kPolicies).
bool SettingApplies(SettingScope scope, const std::string& policy);

// The text form of a setting of an enum type, as the command line, a spec and the records write
// it; Read throws std::invalid_argument naming text that is none of its values.
template <typename T>
struct SettingText;
template <>
struct SettingText<scenarios::Split> {
  static std::string Write(scenarios::Split value) { return scenarios::ToString(value); }
  static scenarios::Split Read(const std::string& text) { return scenarios::ParseSplit(text); }
};
template <>
struct SettingText<CameraProtocol> {
  static std::string Write(CameraProtocol value) { return ToString(value); }
  static CameraProtocol Read(const std::string& text) { return ParseCameraProtocol(text); }
};
template <>
struct SettingText<scenarios::expert::ExpertMode> {
  static std::string Write(scenarios::expert::ExpertMode value) { return scenarios::expert::ToString(value); }
  static scenarios::expert::ExpertMode Read(const std::string& text) {
    return scenarios::expert::ParseExpertMode(text);
  }
};
template <>
struct SettingText<remote::ServingMode> {
  static std::string Write(remote::ServingMode value) { return remote::ToString(value); }
  static remote::ServingMode Read(const std::string& text) { return remote::ParseServingMode(text); }
};

// The setting's value as the records write it (an enum as its text).
nlohmann::json SettingJson(const CellSetting& setting, const EvaluationCellConfig& config);
// True when the setting has its default value (EvaluationCellConfig's).
bool HasDefaultValue(const CellSetting& setting, const EvaluationCellConfig& config);
// Copies the setting's value from one config to another.
void CopySetting(const CellSetting& setting, const EvaluationCellConfig& from, EvaluationCellConfig& to);

// Which record a writer is making.
enum class CellRecord { kCellJson, kSummary };
// The settings `record` holds, as the table says: cell.json's (the settings that decide a cell's
// records; a served policy's where it applies) or summary.json's (a served policy's where
// `served`: the cell was run with one).
nlohmann::json RecordedSettingsJson(const EvaluationCellConfig& config, CellRecord record, bool served);
// The other way: every setting `record` holds (a cell.json's or a summary's settings) read into
// `config`, the others left as they are; keys no setting has (identity) are skipped, and the
// perturbation levels may be written as cell.json writes them ({axis, level, settings} each).
// Throws std::invalid_argument naming the key whose value is of the wrong type or unknown.
void ReadRecordedSettings(const nlohmann::json& record, EvaluationCellConfig& config);

// Checks each setting against the table: its range or choices, and that a setting for other
// policies keeps its default ("replan_steps applies to policy 'openpi' only, got policy
// 'expert'"). Throws output::SettingError naming the first bad one.
void CheckSettingValues(const EvaluationCellConfig& config);

}  // namespace tavis::batch::cell

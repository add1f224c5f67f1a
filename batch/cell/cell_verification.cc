#include "batch/cell/cell_verification.h"

#include <algorithm>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <utility>

#include "batch/action_csv.h"
#include "batch/cell/cell_plan.h"
#include "batch/cell/cell_record_stream.h"
#include "batch/cell/cell_report.h"
#include "batch/cell/evaluation_cell.h"
#include "batch/output/json_error_text.h"
#include "batch/output/program_version.h"
#include "batch/output/settings_difference.h"
#include "batch/policy_kinds.h"
#include "batch/vec_env.h"

namespace tavis::batch::cell {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json ReadJsonFile(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument(path.string() + ": cannot be read");
  try {
    return json::parse(in);
  } catch (const json::exception& error) {
    throw std::invalid_argument(path.string() + ": not valid JSON: " + output::JsonErrorText(error.what()));
  }
}

// A value as a record writes it, a string without its quotes.
std::string Text(const std::optional<json>& value) {
  if (!value) return "absent";
  return value->is_string() ? value->get<std::string>() : value->dump();
}

// The complete lines of episodes.jsonl, each parsed; an interrupted cell's torn last line (no
// newline after it) is left out, as a resume cuts it.
std::vector<json> ReadRecords(const fs::path& cell, bool complete) {
  const fs::path path = cell / "episodes.jsonl";
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(path.string() + ": cannot be read");
  std::vector<json> records;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (in.eof() && !complete) break;
    try {
      records.push_back(json::parse(line));
      records.back().at("episode").get<int64_t>();
    } catch (const json::exception& error) {
      throw std::invalid_argument(path.string() + ":" + std::to_string(number) +
                                  ": not an episode record: " + output::JsonErrorText(error.what()));
    }
  }
  return records;
}

// Why a cell without DIR/actions has none to replay.
std::string NoActionsReason(const EvaluationCellConfig& recorded) {
  std::string policy = "policy '" + recorded.policy + "'";
  if (IsPolicy(recorded.policy, PolicyKind::kExpert)) policy += " at expert_hz " + std::to_string(recorded.expert_hz);
  return "no actions: " + policy +
         " saves none (only a served cell and an expert cell at expert_hz 20 save DIR/actions)";
}

// Ends an episode that its policy ended (the expert gave up; a served reply was unusable, ending
// it invalid_action) where its record says it ended: that end was the policy's decision, which
// actions do not replay.
class EndWhereThePolicyEnded : public EpisodeSink {
 public:
  explicit EndWhereThePolicyEnded(std::map<int64_t, int> ticks) : ticks_(std::move(ticks)) {}
  bool EpisodeComplete(const VecEnv& vec_env, int slot) const override {
    const auto tick = ticks_.find(vec_env.state().episode[slot]);
    return tick != ticks_.end() && vec_env.state().control_step[slot] >= tick->second;
  }
  bool works_per_slot() const override { return true; }

 private:
  std::map<int64_t, int> ticks_;  // episode -> the control tick its policy ended it at
};

bool EndedByPolicy(const json& record) {
  const std::string end = record.value("end", "");
  return end == engine::ToString(engine::EpisodeEnd::kGaveUp) ||
         end == engine::ToString(engine::EpisodeEnd::kInvalidAction);
}

// The settings of the re-simulation: the recorded cell's scene and episodes, its actions replayed.
EvaluationCellConfig ReplayConfig(const EvaluationCellConfig& recorded, const fs::path& cell, int64_t episodes,
                                  const std::string& config_dir) {
  EvaluationCellConfig replay;
  for (const char* key : {"task", "robot", "split", "camera", "seed", "episode_start", "perturbations"})
    CopySetting(CellSettingNamed(key), recorded, replay);
  replay.policy = PolicyName(PolicyKind::kReplay);
  replay.actions_file = (cell / "actions").string();
  replay.config_dir = config_dir;
  replay.episodes = static_cast<int>(episodes);
  replay.first_episode = replay.episode_start;
  return replay;
}

// The re-simulated records, as episodes.jsonl writes them; an episode its policy ended, stopped
// where it ended, takes that end (and the policy's reason) from its record.
std::map<int64_t, json> Resimulate(CellPlan plan, const EvaluationCellConfig& recorded,
                                   const std::map<int64_t, json>& records, const ProgressCallback& progress) {
  // The records the recorded policy's cell keeps (GALT at its own rate: the 60 Hz expert's held
  // actions at 60 Hz, and at 20 Hz), not the replay's.
  const engine::PhysicsSettings& physics = plan.model.physics;
  const bool expert = IsPolicy(recorded.policy, PolicyKind::kExpert);
  plan.record = RecordSettingsFor(recorded, expert ? 1 : physics.controls_per_policy(), physics,
                                  IsPolicy(recorded.policy, PolicyKind::kOpenpi));
  plan.record.replay_stride = 0;
  std::map<int64_t, int> policy_ends;
  for (const auto& [episode, record] : records) {
    if (EndedByPolicy(record)) policy_ends[episode] = record.value("length_control_ticks", 0);
  }
  EndWhereThePolicyEnded stopper(policy_ends);
  const CellResult result = RunEvaluationCell(
      plan, progress, nullptr, [&stopper](const VecEnv&, const auto&) { return std::vector<EpisodeSink*>{&stopper}; });
  std::map<int64_t, json> resimulated;
  for (const EpisodeRecord& episode : result.episodes) {
    json line = json::parse(EpisodeJsonLine(episode, plan.config.seed));
    const auto record = records.find(episode.episode);
    if (episode.end == engine::EpisodeEnd::kStopped && record != records.end() && EndedByPolicy(record->second)) {
      line["end"] = record->second.at("end");
      if (record->second.contains("invalid_action")) line["invalid_action"] = record->second.at("invalid_action");
    }
    resimulated[episode.episode] = std::move(line);
  }
  return resimulated;
}

// Every field of one episode that differs, in VerifiedEpisodeFields' order, then the others. A
// cell another program version wrote may lack the fields this one added since (failure events,
// motion quality): with `older_writer`, a field the record lacks is not compared but named in
// `not_recorded`; a cell of this version must hold every field it writes.
void CompareEpisode(int64_t episode, const std::optional<json>& recorded, const std::optional<json>& now,
                    bool older_writer, std::vector<ValueDifference>& differences, std::set<std::string>& not_recorded) {
  if (!recorded || !now) {
    differences.push_back({episode, "record", recorded ? "present" : "absent", now ? "present" : "absent"});
    return;
  }
  std::vector<std::string> fields = VerifiedEpisodeFields();
  std::set<std::string> others;
  for (const json* side : {&*recorded, &*now}) {
    for (const auto& [key, value] : side->items()) {
      if (std::find(fields.begin(), fields.end(), key) == fields.end()) others.insert(key);
    }
  }
  fields.insert(fields.end(), others.begin(), others.end());
  for (const std::string& field : fields) {
    if (older_writer && !recorded->contains(field) && now->contains(field)) {
      not_recorded.insert(field);
      continue;
    }
    const json was = recorded->contains(field) ? json{{field, recorded->at(field)}} : json::object();
    const json is = now->contains(field) ? json{{field, now->at(field)}} : json::object();
    for (const output::SettingChange& change : output::SettingChanges(was, is))
      differences.push_back({episode, change.path, Text(change.was), Text(change.now)});
  }
}

// The perturbation levels as {"AXIS:LEVEL": settings}, from cell.json's list.
json LevelsByName(const json& list) {
  json levels = json::object();
  if (!list.is_array()) return levels;
  for (const json& level : list) {
    if (level.is_object() && level.contains("axis") && level.contains("level"))
      levels[level.at("axis").get<std::string>() + ":" + level.at("level").get<std::string>()] =
          level.value("settings", json());
  }
  return levels;
}

// What the re-simulation read (the robot file, the levels' files) against what cell.json
// recorded of them. A served policy's key file is not compared: it shaped what the policy was
// sent, not what its actions do.
std::vector<ValueDifference> CompareIdentity(const json& cell_json, const CellPlan& plan) {
  const json recorded_identity = cell_json.value("identity", json::object());
  const json now_settings = CellSettingsJson(plan);
  const json was = {{"identity", {{"robot_config", recorded_identity.value("robot_config", json())}}},
                    {"perturbations", LevelsByName(cell_json.value("perturbations", json::array()))}};
  const json now = {{"identity", {{"robot_config", plan.identity.at("robot_config")}}},
                    {"perturbations", LevelsByName(now_settings.value("perturbations", json::array()))}};
  std::vector<ValueDifference> differences;
  for (const output::SettingChange& change : output::SettingChanges(was, now))
    differences.push_back({-1, change.path, Text(change.was), Text(change.now)});
  return differences;
}

std::string DifferenceText(const ValueDifference& difference, const char* now_word) {
  const std::string where = difference.episode < 0 ? "" : "episode " + std::to_string(difference.episode) + " field ";
  return where + difference.field + ": " + difference.recorded + " recorded, " + difference.now + " " + now_word;
}

const char* OutcomeName(VerifyOutcome outcome) {
  switch (outcome) {
    case VerifyOutcome::kIdentical: return "ok";
    case VerifyOutcome::kDiffers: return "fail";
    case VerifyOutcome::kNoActions: return "no_actions";
  }
  return "";
}

json DifferencesJson(const std::vector<ValueDifference>& differences) {
  json list = json::array();
  for (const ValueDifference& difference : differences) {
    json entry = {{"field", difference.field}, {"recorded", difference.recorded}, {"now", difference.now}};
    if (difference.episode >= 0) entry["episode"] = difference.episode;
    list.push_back(std::move(entry));
  }
  return list;
}

}  // namespace

std::vector<fs::path> FindCells(const fs::path& dir) {
  if (!fs::is_directory(dir)) throw std::invalid_argument(dir.string() + " is not a folder");
  std::vector<fs::path> cells;
  if (fs::exists(dir / "cell.json")) return {dir};
  for (auto entry = fs::recursive_directory_iterator(dir, fs::directory_options::skip_permission_denied);
       entry != fs::recursive_directory_iterator(); ++entry) {
    if (!entry->is_directory() || entry->is_symlink()) continue;
    if (entry->path().filename().string().rfind('.', 0) == 0) {
      entry.disable_recursion_pending();
    } else if (fs::exists(entry->path() / "cell.json")) {
      cells.push_back(entry->path());
      entry.disable_recursion_pending();
    }
  }
  std::sort(cells.begin(), cells.end());
  return cells;
}

const std::vector<std::string>& VerifiedEpisodeFields() {
  static const std::vector<std::string> fields = {"episode",
                                                  "seed",
                                                  "success",
                                                  "end",
                                                  "length_steps",
                                                  "length_control_ticks",
                                                  "galt_s",
                                                  "galt_reason",
                                                  "galt_policy_rate_s",
                                                  "galt_policy_rate_reason",
                                                  "stages",
                                                  "stage_ticks",
                                                  "target",
                                                  "prompt",
                                                  "invalid_action",
                                                  "solver_messages"};
  return fields;
}

int64_t RecordedEpisodeCount(const fs::path& cell) {
  std::ifstream in(cell / "episodes.jsonl", std::ios::binary);
  int64_t lines = 0;
  for (std::string line; std::getline(in, line) && !in.eof();) ++lines;
  return lines;
}

CellVerification VerifyCell(const fs::path& cell, const VerifySettings& settings) {
  CellVerification verification;
  verification.cell = cell;
  const json cell_json = ReadJsonFile(cell / "cell.json");
  EvaluationCellConfig recorded;
  try {
    ReadRecordedSettings(cell_json, recorded);
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument((cell / "cell.json").string() + ": " + error.what());
  }
  verification.program_version_recorded =
      Text(cell_json.value("identity", json::object()).value("program_version", json()));
  verification.program_version_now = output::ProgramVersion();
  verification.complete = fs::exists(cell / "summary.json");
  if (!fs::is_directory(cell / "actions")) {
    verification.outcome = VerifyOutcome::kNoActions;
    verification.no_actions = NoActionsReason(recorded);
    return verification;
  }
  std::map<int64_t, json> records;
  for (json& record : ReadRecords(cell, verification.complete)) {
    const int64_t episode = record.at("episode").get<int64_t>();
    if (!records.emplace(episode, std::move(record)).second)
      throw std::invalid_argument((cell / "episodes.jsonl").string() + ": episode " + std::to_string(episode) +
                                  " is recorded twice");
  }
  // A complete cell holds all its episodes; an interrupted one those it recorded.
  const int64_t episodes = verification.complete ? recorded.episodes : static_cast<int64_t>(records.size());
  std::map<int64_t, json> resimulated;
  CellPlan plan = PlanCell(ReplayConfig(recorded, cell, std::max<int64_t>(episodes, 1), settings.config_dir));
  for (int64_t episode = recorded.episode_start; episode < recorded.episode_start + episodes; ++episode) {
    if (FindEpisodeActions(cell / "actions", episode).empty())
      throw std::invalid_argument((cell / "actions" / EpisodeActionsName(episode)).string() +
                                  ": missing (nor a plain episode_" + std::to_string(episode) +
                                  ".csv): the cell's actions are incomplete");
  }
  if (episodes > 0) resimulated = Resimulate(plan, recorded, records, settings.progress);
  verification.identity = CompareIdentity(cell_json, plan);
  std::set<int64_t> indices;
  for (const auto& [episode, record] : records) indices.insert(episode);
  for (const auto& [episode, record] : resimulated) indices.insert(episode);
  for (const int64_t episode : indices) {
    const auto was = records.find(episode);
    const auto now = resimulated.find(episode);
    const std::size_t before = verification.records.size();
    CompareEpisode(episode, was == records.end() ? std::nullopt : std::optional<json>(was->second),
                   now == resimulated.end() ? std::nullopt : std::optional<json>(now->second),
                   verification.program_version_differs(), verification.records, verification.fields_not_recorded);
    verification.identical += verification.records.size() == before ? 1 : 0;
  }
  verification.episodes = static_cast<int64_t>(indices.size());
  const bool differs = !verification.identity.empty() || !verification.records.empty();
  verification.outcome = differs ? VerifyOutcome::kDiffers : VerifyOutcome::kIdentical;
  return verification;
}

std::string VerificationLine(const CellVerification& verification, const std::string& name) {
  if (verification.outcome == VerifyOutcome::kNoActions)
    return "skip " + name + ": cannot verify: " + verification.no_actions;
  const std::string counts = std::to_string(verification.identical) + "/" + std::to_string(verification.episodes) +
                             " episodes identical" + (verification.complete ? "" : " (incomplete: no summary.json)");
  std::string unrecorded;
  for (const std::string& field : verification.fields_not_recorded)
    unrecorded += (unrecorded.empty() ? "" : ", ") + field;
  const std::string not_compared =
      unrecorded.empty() ? "" : " (not in the older records, not compared: " + unrecorded + ")";
  if (verification.outcome == VerifyOutcome::kIdentical) return "ok   " + name + ": " + counts + not_compared;
  std::string line = "FAIL " + name + ": ";
  if (!verification.identity.empty()) line += DifferenceText(verification.identity.front(), "now") + "; ";
  if (!verification.records.empty()) line += DifferenceText(verification.records.front(), "re-simulated") + "; ";
  return line + counts;
}

json VerificationJson(const CellVerification& verification, const std::string& name) {
  json entry = {{"cell", name},
                {"path", verification.cell.string()},
                {"outcome", OutcomeName(verification.outcome)},
                {"complete", verification.complete},
                {"program_version",
                 {{"recorded", verification.program_version_recorded}, {"now", verification.program_version_now}}}};
  if (verification.outcome == VerifyOutcome::kNoActions) {
    entry["reason"] = verification.no_actions;
    return entry;
  }
  entry["episodes"] = verification.episodes;
  entry["identical"] = verification.identical;
  entry["identity_differences"] = DifferencesJson(verification.identity);
  entry["record_differences"] = DifferencesJson(verification.records);
  entry["fields_not_recorded"] = verification.fields_not_recorded;
  return entry;
}

}  // namespace tavis::batch::cell

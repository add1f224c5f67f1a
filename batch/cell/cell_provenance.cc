#include "batch/cell/cell_provenance.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <utility>

#include "batch/cell/episode_times.h"
#include "batch/output/config_identity.h"
#include "batch/output/sha256.h"
#include "batch/perturb/perturbation_catalog.h"
#include "batch/policy_kinds.h"
#include "batch/remote/server_contract.h"
#include "batch/remote/value_json.h"

namespace tavis::batch::cell {
namespace {

bool IsSha256Hex(const std::string& text) {
  return text.size() == 64 &&
         std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isxdigit(c) != 0; });
}

// A string value of `frame`'s key `key`, or null.
const std::string* StringAt(const remote::Value& frame, const char* key) {
  const remote::Value* value = frame.Find(key);
  return value != nullptr ? value->get_if<std::string>() : nullptr;
}

nlohmann::json FilesJson(const std::vector<output::ConfigFile>& files) {
  nlohmann::json json = nlohmann::json::object();
  for (const output::ConfigFile& file : files) {
    try {
      json.update(output::ConfigFilesJson({file}));
    } catch (const std::exception& error) {
      json[file.first] = {{"file", file.second.filename().string()}, {"error", error.what()}};
    }
  }
  return json;
}

nlohmann::json PolicyJson(const CellResult& result, const ProvenanceRun& run) {
  const EvaluationCellConfig& config = result.config;
  nlohmann::json policy = {{"label", run.label.empty() ? config.policy : run.label}, {"name", config.policy}};
  if (!IsPolicy(config.policy, PolicyKind::kOpenpi)) return policy;
  policy["servers"] = config.servers;
  nlohmann::json frames = nlohmann::json::array();
  nlohmann::json checkpoints = nlohmann::json::array();
  nlohmann::json trained_for = nlohmann::json::array();
  bool declares_trained_for = false;
  for (const remote::Value& frame : result.server_metadata) {
    frames.push_back(RecordedMetadataFrame(frame));
    const std::string checkpoint = DeclaredCheckpointSha256(frame);
    checkpoints.push_back(checkpoint.empty() ? nlohmann::json() : nlohmann::json(checkpoint));
    trained_for.push_back(DeclaredTrainedFor(frame));
    declares_trained_for = declares_trained_for || !trained_for.back().is_null();
  }
  policy["server_metadata"] = frames;
  policy["checkpoint_sha256"] = checkpoints;  // per server, null where it declares none
  // Only where a server declares one, so that the records of every other cell stay as they were.
  if (declares_trained_for) policy["trained_for"] = trained_for;  // per server, null where it declares none
  return policy;
}

nlohmann::json TimeJson(const CellResult& result) {
  nlohmann::json time = {{"wall_s", result.wall_s}};
  if (result.requests) {
    const double wait_s = result.requests->wait_ms / 1000.0;
    time["policy_wait_s"] = wait_s;
    time["simulation_s"] = std::max(0.0, result.wall_s - wait_s);
  }
  std::vector<EpisodeTimes> measured;
  for (const EpisodeRecord& record : result.episodes) {
    if (record.times) measured.push_back(*record.times);
  }
  time["episodes"] = EpisodeTimesSummaryJson(measured);
  if (result.profile) {
    nlohmann::json stages = nlohmann::json::object();
    for (const auto& [stage, seconds] : result.profile->stages) stages[stage] = seconds;
    time["stages_s"] = stages;
  }
  return time;
}

}  // namespace

std::vector<output::ConfigFile> CellConfigFiles(const EvaluationCellConfig& config) {
  // The robot file where RobotConfigPath looks for it (here without its check: a file gone since
  // the cell ran is recorded as unreadable).
  std::vector<output::ConfigFile> files = {
      {"robot", std::filesystem::path(config.config_dir) / "robots" / (config.robot + ".yaml")}};
  if (IsPolicy(config.policy, PolicyKind::kOpenpi)) {
    const std::string keys = output::ObservationKeysIdentityFile(config.config_dir, config.observation_keys);
    if (!keys.empty()) files.emplace_back("observation_keys", keys);
  }
  for (const std::string& choice : config.perturbations) {
    const std::string axis = perturb::ParsePerturbationChoice(choice).axis;
    files.emplace_back("perturbations/" + axis, config.config_dir + "/perturbations/" + axis + ".yaml");
  }
  return files;
}

nlohmann::json RecordedMetadataFrame(const remote::Value& frame) {
  nlohmann::json json = remote::ToJson(frame);
  const std::string text = json.dump();
  if (text.size() <= kMaxRecordedMetadataBytes) return json;
  nlohmann::json keys = nlohmann::json::array();
  if (json.is_object()) {
    for (const auto& [key, value] : json.items()) {
      if (keys.size() == 32) break;
      keys.push_back(key.substr(0, 256));
    }
  }
  return {{"omitted", "the frame's JSON is over " + std::to_string(kMaxRecordedMetadataBytes) + " bytes"},
          {"json_bytes", text.size()},
          {"sha256", "sha256:" + output::Sha256Hex(text)},
          {"keys", keys}};
}

std::string DeclaredCheckpointSha256(const remote::Value& frame) {
  if (!frame.is<remote::Value::Map>()) return "";
  const std::string* hash = StringAt(frame, "checkpoint_sha256");
  // The contract the reference server declares (batch/remote/server_contract.h) carries it too.
  const std::pair<const char*, const char*> nested[] = {{"observation_contract", "checkpoint_sha256"},
                                                        {"checkpoint", "sha256"}};
  for (const auto& [section, key] : nested) {
    if (hash != nullptr) break;
    const remote::Value* inner = frame.Find(section);
    if (inner != nullptr && inner->is<remote::Value::Map>()) hash = StringAt(*inner, key);
  }
  if (hash == nullptr) return "";
  std::string hex = hash->rfind("sha256:", 0) == 0 ? hash->substr(7) : *hash;
  std::transform(hex.begin(), hex.end(), hex.begin(), [](unsigned char c) { return std::tolower(c); });
  return IsSha256Hex(hex) ? "sha256:" + hex : "";
}

nlohmann::json DeclaredTrainedFor(const remote::Value& frame) {
  std::optional<remote::ServerContract> contract;
  try {
    contract = remote::ParseServerContract(frame, "");
  } catch (const std::invalid_argument&) {
    return nullptr;  // a malformed contract declares nothing here (the cell refused it before it ran)
  }
  if (!contract || (contract->task.empty() && contract->robot.empty())) return nullptr;
  nlohmann::json declared = nlohmann::json::object();
  if (!contract->task.empty()) declared["task"] = contract->task;
  if (!contract->robot.empty()) declared["robot"] = contract->robot;
  return declared;
}

nlohmann::json CellProvenanceJson(const CellResult& result, const ProvenanceRun& run) {
  std::vector<output::ConfigFile> files;
  try {
    files = CellConfigFiles(result.config);
  } catch (const std::exception&) {
    // A perturbation choice that no longer parses cannot happen in a cell that ran; no files then.
  }
  return {{"program", output::ProgramProvenanceJson()},
          {"config_files", FilesJson(files)},
          {"policy", PolicyJson(result, run)},
          {"machine", output::MachineJson(run.threads)},
          {"time", TimeJson(result)}};
}

}  // namespace tavis::batch::cell

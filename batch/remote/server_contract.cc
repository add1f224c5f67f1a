#include "batch/remote/server_contract.h"

#include <algorithm>
#include <cstdint>
#include <map>
#include <stdexcept>

#include "batch/camera_protocol.h"
#include "batch/observation_contract.h"
#include "batch/scene_render.h"

namespace tavis::batch::remote {
namespace {

constexpr std::size_t kMaxKeyBytes = 256;
constexpr std::int64_t kMaxImageSide = 4096;
constexpr std::int64_t kMaxStateSize = 4096;
constexpr std::int64_t kMaxHistory = 10000;
constexpr std::int64_t kMaxChunk = 100000;
constexpr std::size_t kMaxNameBytes = 64;

const char* const kFields[] = {"version",     "cameras",      "image_width",    "image_height",      "state",
                               "n_obs_steps", "chunk_length", "executed_steps", "checkpoint_sha256", "task",
                               "robot"};

class ContractReader {
 public:
  ContractReader(const Value& contract, std::string server) : server_(std::move(server)) {
    const Value::Map* map = contract.get_if<Value::Map>();
    if (map == nullptr) Fail("", "must be a map, got " + contract.TypeName());
    for (const MapEntry& entry : *map) {
      const std::string* key = entry.key.get_if<std::string>();
      if (key == nullptr) Fail("", "has a key of type " + entry.key.TypeName() + "; every key is a str");
      if (std::find(std::begin(kFields), std::end(kFields), *key) == std::end(kFields)) {
        Fail("", "has the unknown field '" + Shown(*key) +
                     "' (known: version, cameras, image_width, image_height, "
                     "state, n_obs_steps, chunk_length, executed_steps, checkpoint_sha256, task, robot)");
      }
      if (fields_.count(*key) > 0) Fail(*key, "is given twice");
      fields_.emplace(*key, &entry.value);
    }
  }

  [[noreturn]] void Fail(const std::string& field, const std::string& what) const {
    throw std::invalid_argument("policy server " + server_ + ": " + kServerContractMetadata +
                                (field.empty() ? "" : "." + field) + " " + what);
  }

  const Value* Optional(const std::string& field) const {
    const auto found = fields_.find(field);
    return found == fields_.end() ? nullptr : found->second;
  }

  const Value& Required(const std::string& field) const {
    const Value* value = Optional(field);
    if (value == nullptr) Fail(field, "is missing");
    return *value;
  }

  int Int(const Value& value, const std::string& field, std::int64_t low, std::int64_t high) const {
    const std::int64_t* number = value.get_if<std::int64_t>();
    if (number == nullptr) Fail(field, "must be an int, got " + value.TypeName());
    if (*number < low || *number > high) {
      Fail(field,
           "must be from " + std::to_string(low) + " to " + std::to_string(high) + ", got " + std::to_string(*number));
    }
    return static_cast<int>(*number);
  }

  int Int(const std::string& field, std::int64_t low, std::int64_t high) const {
    return Int(Required(field), field, low, high);
  }

  // A key the client sends under: 1 to 256 printable ASCII characters, not a request field.
  std::string Key(const Value& value, const std::string& field) const {
    const std::string* text = value.get_if<std::string>();
    if (text == nullptr) Fail(field, "must be a str, got " + value.TypeName());
    if (text->empty() || text->size() > kMaxKeyBytes) {
      Fail(field, "must be 1 to " + std::to_string(kMaxKeyBytes) + " characters, got " + std::to_string(text->size()));
    }
    if (!std::all_of(text->begin(), text->end(), [](char c) { return c > 0x20 && c < 0x7f; })) {
      Fail(field, "must be printable ASCII without spaces, got '" + Shown(*text) + "'");
    }
    for (const char* request_field : batch::contract::kRequestFields) {
      if (*text == request_field) Fail(field, "is '" + *text + "', which every request carries as a request field");
    }
    return *text;
  }

  const std::string& server() const { return server_; }

  // At most 64 printable characters of a peer's text, for a message.
  static std::string Shown(const std::string& text) {
    std::string shown;
    for (char c : text.substr(0, 64)) shown += (c >= 0x20 && c < 0x7f) ? c : '?';
    return text.size() > 64 ? shown + "..." : shown;
  }

 private:
  std::string server_;
  std::map<std::string, const Value*> fields_;
};

void ReadCameras(const ContractReader& reader, ServerContract& contract) {
  const Value& cameras = reader.Required("cameras");
  const Value::Map* map = cameras.get_if<Value::Map>();
  if (map == nullptr) reader.Fail("cameras", "must be a map of camera -> key, got " + cameras.TypeName());
  const std::vector<std::string>& known = batch::SceneCameraNames();
  std::vector<std::pair<std::string, KeyPath>> listed;
  for (const MapEntry& entry : *map) {
    const std::string* camera = entry.key.get_if<std::string>();
    if (camera == nullptr) reader.Fail("cameras", "has a key of type " + entry.key.TypeName());
    if (std::find(known.begin(), known.end(), *camera) == known.end()) {
      reader.Fail("cameras", "names the unknown camera '" + ContractReader::Shown(*camera) +
                                 "' (known: head, fixed, left_wrist, right_wrist)");
    }
    for (const auto& [name, key] : listed) {
      if (name == *camera) reader.Fail("cameras." + *camera, "is given twice");
    }
    listed.emplace_back(*camera, KeyPath{reader.Key(entry.value, "cameras." + *camera)});
  }
  // In the order of SceneCameraNames(), as every layout lists them.
  for (const std::string& name : known) {
    for (const auto& entry : listed) {
      if (entry.first == name) contract.keys.cameras.push_back(entry);
    }
  }
  const auto has = [&contract](const char* name) {
    return std::any_of(contract.keys.cameras.begin(), contract.keys.cameras.end(),
                       [name](const auto& entry) { return entry.first == name; });
  };
  if (has("fixed") && !has("head"))
    reader.Fail("cameras",
                "has fixed, which replaces head under the fixed protocol, "
                "but no head");
  if (contract.keys.PolicyCameras().empty()) {
    reader.Fail("cameras", "names no camera for the policy (at least one of head, left_wrist, right_wrist)");
  }
}

void ReadState(const ContractReader& reader, ServerContract& contract) {
  const Value& state = reader.Required("state");
  const Value::Map* map = state.get_if<Value::Map>();
  if (map == nullptr) reader.Fail("state", "must be a map {key, size}, got " + state.TypeName());
  const Value* key = nullptr;
  const Value* size = nullptr;
  for (const MapEntry& entry : *map) {
    const std::string* name = entry.key.get_if<std::string>();
    const Value** slot = name == nullptr ? nullptr : *name == "key" ? &key : *name == "size" ? &size : nullptr;
    if (slot == nullptr) reader.Fail("state", "holds a field other than key and size");
    if (*slot != nullptr) reader.Fail("state." + *name, "is given twice");
    *slot = &entry.value;
  }
  if (key == nullptr || size == nullptr) reader.Fail("state", "must give both key and size");
  contract.keys.state = {reader.Key(*key, "state.key")};
  contract.state_size = reader.Int(*size, "state.size", 1, kMaxStateSize);
}

// No two keys of the request may be the same: one value would overwrite the other.
void CheckDistinctKeys(const ContractReader& reader, const ServerContract& contract) {
  std::vector<std::pair<std::string, std::string>> sent;  // what, key
  for (const auto& [camera, key] : contract.keys.cameras) {
    if (camera != "fixed") sent.emplace_back("cameras." + camera, key.front());
  }
  sent.emplace_back("state.key", contract.keys.state.front());
  sent.emplace_back("the prompt", contract.keys.prompt.front());
  sent.emplace_back("the task", contract.keys.task.front());
  for (std::size_t i = 0; i < sent.size(); ++i) {
    for (std::size_t j = i + 1; j < sent.size(); ++j) {
      if (sent[i].second == sent[j].second) {
        reader.Fail(sent[i].first, "and " + sent[j].first + " are both '" + sent[i].second + "'");
      }
    }
  }
}

bool IsLowerHex(const std::string& text) {
  return std::all_of(text.begin(), text.end(), [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); });
}

// A tavis name (a task's, a robot's) the contract may give: 1 to 64 lower-case letters, digits,
// '-' or '_', the first a letter or digit. Only its form is checked: which names exist is the
// cell's to know, and a name of another task or robot is a conflict (TrainedForConflicts), not
// a malformed contract. "" when the field is not given.
std::string OptionalName(const ContractReader& reader, const std::string& field) {
  const Value* value = reader.Optional(field);
  if (value == nullptr) return "";
  const std::string* text = value->get_if<std::string>();
  if (text == nullptr) reader.Fail(field, "must be a str, got " + value->TypeName());
  const auto allowed = [](char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == '_'; };
  if (text->empty() || text->size() > kMaxNameBytes || !std::all_of(text->begin(), text->end(), allowed) ||
      text->front() == '-' || text->front() == '_') {
    reader.Fail(field, "must be a tavis name of 1 to " + std::to_string(kMaxNameBytes) +
                           " lower-case letters, digits, '-' or '_' (e.g. conditional-pick, gr1t2), got '" +
                           ContractReader::Shown(*text) + "' (" + std::to_string(text->size()) + " bytes)");
  }
  return *text;
}

}  // namespace

std::optional<ServerContract> ParseServerContract(const Value& metadata, const std::string& server) {
  const Value* declared = metadata.Find(kServerContractMetadata);
  if (declared == nullptr) return std::nullopt;
  const ContractReader reader(*declared, server);
  reader.Int("version", kServerContractVersion, kServerContractVersion);
  ServerContract contract;
  contract.server = server;
  contract.keys = ContractKeys();  // the prompt and task keys, HWC, no letterbox
  contract.keys.source = "policy server " + server + "'s " + kServerContractMetadata;
  contract.keys.cameras.clear();
  ReadCameras(reader, contract);
  contract.keys.image_width = reader.Int("image_width", 8, kMaxImageSide);
  contract.keys.image_height = reader.Int("image_height", 8, kMaxImageSide);
  ReadState(reader, contract);
  CheckDistinctKeys(reader, contract);
  contract.n_obs_steps = reader.Int("n_obs_steps", 1, kMaxHistory);
  contract.chunk_length = reader.Int("chunk_length", 1, kMaxChunk);
  contract.executed_steps = reader.Int("executed_steps", 1, contract.chunk_length);
  if (contract.n_obs_steps > 1 && contract.executed_steps != 1) {
    reader.Fail("executed_steps", "is " + std::to_string(contract.executed_steps) + ", but n_obs_steps " +
                                      std::to_string(contract.n_obs_steps) +
                                      " needs an observation at every step (executed_steps 1)");
  }
  if (const Value* sha = reader.Optional("checkpoint_sha256")) {
    const std::string* text = sha->get_if<std::string>();
    if (text == nullptr) reader.Fail("checkpoint_sha256", "must be a str, got " + sha->TypeName());
    if (text->size() != 64 || !IsLowerHex(*text)) {
      reader.Fail("checkpoint_sha256", "must be 64 lower-case hex digits, got '" + ContractReader::Shown(*text) + "'");
    }
    contract.checkpoint_sha256 = *text;
  }
  contract.task = OptionalName(reader, "task");
  contract.robot = OptionalName(reader, "robot");
  return contract;
}

std::vector<std::string> ContractConflicts(const ServerContract& contract, const ObservationKeys& sent,
                                           int replan_steps, int state_size) {
  std::vector<std::string> conflicts = LayoutDifferences(sent, contract.keys);
  if (contract.state_size != state_size) {
    conflicts.push_back("state size: this robot's observation.state has " + std::to_string(state_size) + " entries, " +
                        contract.keys.source + " declares " + std::to_string(contract.state_size) +
                        " (a policy of another robot?)");
  }
  const int executed = replan_steps == 0 ? contract.chunk_length : replan_steps;
  if (executed != contract.executed_steps) {
    conflicts.push_back("executed steps: the cell executes " +
                        (replan_steps == 0 ? "the whole chunk (" + std::to_string(executed) + " rows)"
                                           : std::to_string(replan_steps) + " rows") +
                        " of each reply, " + contract.keys.source + " declares executed_steps " +
                        std::to_string(contract.executed_steps));
  }
  return conflicts;
}

std::vector<std::string> TrainedForConflicts(const ServerContract& contract, const std::string& task,
                                             const std::string& robot) {
  std::vector<std::string> conflicts;
  const auto compare = [&](const char* what, const std::string& trained, const char* cell_is, const std::string& cell) {
    if (trained.empty() || trained == cell) return;
    conflicts.push_back("policy server " + contract.server + "'s policy was trained for " + what + " " + trained +
                        "; " + cell_is + " " + cell);
  };
  compare("task", contract.task, "this cell is", task);
  compare("robot", contract.robot, "this cell's robot is", robot);
  return conflicts;
}

}  // namespace tavis::batch::remote

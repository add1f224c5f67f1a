#include "batch/cell/declared_contract.h"

#include <chrono>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "batch/cell/cell_plan.h"
#include "batch/output/setting_error.h"
#include "batch/policy_kinds.h"
#include "batch/remote/remote_policy.h"

namespace tavis::batch::cell {
namespace {

std::string Lines(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += (text.empty() ? "" : "; ") + line;
  return text;
}

std::string Size(int width, int height) { return std::to_string(width) + "x" + std::to_string(height); }

}  // namespace

std::optional<remote::ServerContract> ReadDeclaredContract(const EvaluationCellConfig& config) {
  if (!IsPolicy(config.policy, PolicyKind::kOpenpi) || config.servers.empty()) return std::nullopt;
  CheckServerUrls(config);  // a bad URL is a setting's error (naming --server), not a connection's
  remote::RemotePolicyOptions options;
  options.ready_timeout = std::chrono::milliseconds(static_cast<int64_t>(config.server_ready_timeout_s * 1000.0));
  options.reply_timeout = std::chrono::milliseconds(static_cast<int64_t>(config.reply_timeout_s * 1000.0));
  options.max_reply_bytes = static_cast<std::uint64_t>(config.max_reply_mb * 1024.0 * 1024.0);
  const std::string& server = config.servers.front();
  return remote::ParseServerContract(remote::ReadServerMetadata(server, options), server);
}

remote::ObservationKeys AdoptDeclaredContract(EvaluationCellConfig& config,
                                              const std::optional<remote::ObservationKeys>& dataset, int state_size) {
  const remote::ServerContract& contract = *config.declared_contract;
  const remote::ObservationKeys& declared = contract.keys;
  // A policy trained for another task or robot would run and score about 0: refused first, since
  // no option can make it this cell's.
  const std::vector<std::string> trained_for = remote::TrainedForConflicts(contract, config.task, config.robot);
  if (!trained_for.empty()) {
    throw output::SettingsAdvice<std::invalid_argument>(
        Lines(trained_for) + " (serve a checkpoint trained for this cell's task and robot, or give " +
        output::SettingKey("task") + " and " + output::SettingKey("robot") + " of the one served)");
  }
  const std::string against = "contradicts the contract policy server " + contract.server + " declares: ";
  if (config.observation_keys_given) {
    remote::ObservationKeys given = remote::LoadObservationKeys(config.observation_keys, config.config_dir);
    given.image_width = declared.image_width;  // the size is --image-size's to contradict
    given.image_height = declared.image_height;
    const std::vector<std::string> differences = remote::LayoutDifferences(given, declared);
    if (!differences.empty()) {
      throw output::SettingError("observation_keys", config.observation_keys + " " + against + Lines(differences));
    }
  }
  if (dataset) {
    const std::vector<std::string> differences = remote::LayoutDifferences(*dataset, declared);
    if (!differences.empty()) {
      throw output::SettingError("observation_dataset",
                                 config.observation_dataset + " " + against + Lines(differences));
    }
  }
  if (config.image_width != 0 &&
      (config.image_width != declared.image_width || config.image_height != declared.image_height)) {
    throw output::SettingError("image_width", Size(config.image_width, config.image_height) + " " + against +
                                                  "image size " + Size(declared.image_width, declared.image_height));
  }
  if (config.replan_steps_given) {
    const int executed = config.replan_steps == 0 ? contract.chunk_length : config.replan_steps;
    if (executed != contract.executed_steps) {
      throw output::SettingError("replan_steps", std::to_string(config.replan_steps) + " " + against +
                                                     "executed_steps " + std::to_string(contract.executed_steps) +
                                                     " (chunk_length " + std::to_string(contract.chunk_length) +
                                                     ", n_obs_steps " + std::to_string(contract.n_obs_steps) + ")");
    }
  }
  if (contract.state_size != state_size) {
    throw std::invalid_argument("policy server " + contract.server + " declares an observation.state of " +
                                std::to_string(contract.state_size) + " entries, but robot " + config.robot +
                                "'s has " + std::to_string(state_size) + " (a policy of another robot?)");
  }
  config.replan_steps = contract.executed_steps;
  return declared;
}

}  // namespace tavis::batch::cell

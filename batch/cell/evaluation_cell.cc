#include "batch/cell/evaluation_cell.h"

#include <algorithm>
#include <chrono>
#include <optional>
#include <stdexcept>
#include <tuple>

#include "batch/builtin_policies.h"
#include "batch/perturbation_catalog.h"
#include "batch/policy_kinds.h"
#include "batch/vec_env.h"
#include "configs/robot_config.h"
#include "scenarios/registry.h"

namespace tavis::batch::cell {
namespace {

void ValidatePolicy(const EvaluationCellConfig& config) {
  if (IsPolicy(config.policy, PolicyKind::kOpenpi)) {
    if (config.servers.empty())
      throw std::invalid_argument("policy 'openpi' needs a policy server (--server ws://HOST:PORT)");
    return;
  }
  try {
    CheckBuiltinPolicyName(config.policy);
  } catch (const std::invalid_argument&) {
    throw std::invalid_argument("unknown policy '" + config.policy + "' (known: " + CellPolicyNames() + ")");
  }
  if (!config.servers.empty())
    throw std::invalid_argument("--server is for --policy openpi, not '" + config.policy + "'");
}

void ValidateExpertMode(const EvaluationCellConfig& config) {
  if (config.expert_mode != scenarios::expert::ExpertMode::kGazeFirst &&
      !IsPolicy(config.policy, PolicyKind::kExpert)) {
    throw std::invalid_argument(std::string("--expert-mode ") + scenarios::expert::ToString(config.expert_mode) +
                                " is for --policy expert, not '" + config.policy + "'");
  }
}

struct ServedLayout {
  remote::ObservationKeys keys;
  std::vector<std::string> differences;  // from the dataset named alongside
};

// The served policy's request layout: the dataset's when one is named and no keys are, else the
// keys' (preset or file), with an explicit image size taking the place of its own; a layout that
// differs from a dataset named alongside is reported.
ServedLayout ServedKeys(const EvaluationCellConfig& config, int state_size) {
  ServedLayout layout;
  std::optional<remote::ObservationKeys> dataset;
  if (!config.observation_dataset.empty()) dataset = remote::LoadDatasetKeys(config.observation_dataset, state_size);
  layout.keys = dataset && !config.observation_keys_given
                    ? *dataset
                    : remote::LoadObservationKeys(config.observation_keys, config.config_dir);
  if (config.image_width != 0) {
    layout.keys.image_width = config.image_width;
    layout.keys.image_height = config.image_height;
  }
  if (dataset) layout.differences = remote::LayoutDifferences(layout.keys, *dataset);
  return layout;
}

// The policy's cameras under the camera protocol first (its images keep their order), then the
// extra cameras to render.
std::vector<std::string> CamerasToRender(const Policy& policy, const EvaluationCellConfig& config) {
  std::vector<std::string> cameras = ProtocolCameras(policy.cameras(), config.camera);
  for (const std::string& name : config.render_cameras) {
    if (std::find(cameras.begin(), cameras.end(), name) == cameras.end()) cameras.push_back(name);
  }
  return cameras;
}

}  // namespace

// What the recorder keeps: GALT sampled when the policy acted (every `hold_ticks` control ticks),
// as the reference records actions at its policy rate, and for a policy acting faster also at the
// 20 Hz policy rate; none under the fixed protocol, where there is no head to lead.
RecordSettings RecordSettingsFor(const EvaluationCellConfig& config, int hold_ticks,
                                 const engine::PhysicsSettings& physics, bool served) {
  RecordSettings settings;
  if (!UsesFixedView(config.camera)) {
    settings.galt_stride = hold_ticks;
    settings.galt_fps = physics.control_hz / hold_ticks;
    const int policy_stride = physics.controls_per_policy();
    if (hold_ticks < policy_stride) {
      settings.policy_rate_stride = policy_stride;
      settings.policy_rate_fps = physics.control_hz / policy_stride;
    }
  }
  // A served policy's chunks, and a 20 Hz expert's held actions, are kept at the policy rate for
  // --policy replay, which plays them back exactly.
  const bool expert_at_policy_rate = IsPolicy(config.policy, PolicyKind::kExpert) && config.expert_hz != 60;
  settings.replay_stride = served ? hold_ticks : expert_at_policy_rate ? physics.controls_per_policy() : 0;
  settings.keep_actions = config.keep_actions;
  return settings;
}

std::string CellPolicyNames() { return PolicyNames(/*built_in_only=*/false); }

void CheckEvaluationCell(const EvaluationCellConfig& config) {
  if (config.episodes < 1)
    throw std::invalid_argument("--episodes must be at least 1, got " + std::to_string(config.episodes));
  if (config.envs < 1) throw std::invalid_argument("--envs must be at least 1, got " + std::to_string(config.envs));
  if (config.episode_start < 0) {
    throw std::invalid_argument("--episode must be at least 0, got " + std::to_string(config.episode_start));
  }
  const int64_t end = config.episode_start + config.episodes;
  if (config.first_episode < config.episode_start || config.first_episode > end) {
    throw std::invalid_argument("the first episode to run must be in [" + std::to_string(config.episode_start) + ", " +
                                std::to_string(end) + "], got " + std::to_string(config.first_episode));
  }
  ValidatePolicy(config);
  if (config.expert_hz != 60 && config.expert_hz != 20) {
    throw std::invalid_argument("--expert-hz must be 60 or 20, got " + std::to_string(config.expert_hz));
  }
  if (config.expert_hz != 60 && !IsPolicy(config.policy, PolicyKind::kExpert)) {
    throw std::invalid_argument("--expert-hz applies to --policy expert only, got --policy " + config.policy);
  }
  ValidateExpertMode(config);
  if ((config.image_width == 0) != (config.image_height == 0)) {
    throw std::invalid_argument("give both image dimensions or neither, got " + std::to_string(config.image_width) +
                                "x" + std::to_string(config.image_height));
  }
  CameraSettings cameras;
  cameras.cameras = config.render_cameras;
  if (config.image_width != 0) {
    cameras.width = config.image_width;
    cameras.height = config.image_height;
  }
  ValidateCameraSettings(cameras);
  scenarios::FindScenario(config.task);
  const kinematics::RobotModel robot =
      configs::LoadRobotModel(configs::RobotConfigPath(config.config_dir, config.robot));
  ResolvePerturbations(config.config_dir, config.perturbations);
  if (IsPolicy(config.policy, PolicyKind::kOpenpi)) {
    ServedKeys(config, static_cast<int>(robot.observation_state.size()));
  } else if (!config.observation_dataset.empty()) {
    throw std::invalid_argument("--match-dataset '" + config.observation_dataset +
                                "' applies to --policy openpi only, got --policy " + config.policy);
  }
}

std::vector<std::string> ServedLayoutDifferences(const EvaluationCellConfig& config) {
  if (!IsPolicy(config.policy, PolicyKind::kOpenpi) || config.observation_dataset.empty()) return {};
  const kinematics::RobotModel robot =
      configs::LoadRobotModel(configs::RobotConfigPath(config.config_dir, config.robot));
  return ServedKeys(config, static_cast<int>(robot.observation_state.size())).differences;
}

bool RunsPerSlot(const EvaluationCellConfig& config) { return !IsPolicy(config.policy, PolicyKind::kOpenpi); }

int DefaultEnvs(const std::string& policy, int threads) {
  constexpr int kDefaultEnvs = 32;
  constexpr int kServedEnvsPerThread = 6;
  return IsPolicy(policy, PolicyKind::kOpenpi) ? std::max(kDefaultEnvs, kServedEnvsPerThread * threads) : kDefaultEnvs;
}

CellResult RunEvaluationCell(const EvaluationCellConfig& config, const ProgressCallback& progress,
                             const RecordCallback& on_record, const CellSinks& sinks) {
  CheckEvaluationCell(config);
  const scenarios::ScenarioDef& scenario = scenarios::FindScenario(config.task);
  const kinematics::RobotModel robot =
      configs::LoadRobotModel(configs::RobotConfigPath(config.config_dir, config.robot));
  const auto start = std::chrono::steady_clock::now();

  const int64_t end_episode = config.episode_start + config.episodes;
  const int slots = static_cast<int>(std::clamp<int64_t>(end_episode - config.first_episode, 1, config.envs));
  engine::WorldModel model = BuildWorldModel(robot, scenario);
  ApplyPerturbations(config.config_dir, config.perturbations, config.seed, &model);
  VecEnv vec_env(std::move(model), scenario, config.split, slots, config.seed);
  CellResult result;
  result.config = config;
  std::unique_ptr<Policy> policy;
  remote::RemotePolicy* served = nullptr;
  if (IsPolicy(config.policy, PolicyKind::kOpenpi)) {
    remote::RemotePolicyOptions options;
    options.servers = config.servers;
    options.replan_steps = config.replan_steps;
    options.mode = config.serving;
    ServedLayout layout = ServedKeys(config, static_cast<int>(robot.observation_state.size()));
    options.keys = std::move(layout.keys);
    result.layout_differences = std::move(layout.differences);
    options.protocol = config.camera;
    options.ready_timeout = std::chrono::milliseconds(static_cast<int64_t>(config.server_ready_timeout_s * 1000.0));
    options.reply_timeout = std::chrono::milliseconds(static_cast<int64_t>(config.reply_timeout_s * 1000.0));
    options.max_reply_bytes = static_cast<std::uint64_t>(config.max_reply_mb * 1024.0 * 1024.0);
    result.config.image_width = options.keys.image_width;
    result.config.image_height = options.keys.image_height;
    std::tie(result.render_width, result.render_height) = remote::RenderSize(options.keys);
    result.observation_keys_source = options.keys.source;
    auto remote_policy = std::make_unique<remote::RemotePolicy>(options, slots);
    served = remote_policy.get();
    policy = std::move(remote_policy);
  } else {
    if (config.image_width == 0) {
      const CameraSettings reference;
      result.config.image_width = reference.width;
      result.config.image_height = reference.height;
    }
    result.render_width = result.config.image_width;
    result.render_height = result.config.image_height;
    if (IsPolicy(config.policy, PolicyKind::kExpert)) {
      const int control_hz = static_cast<int>(vec_env.model().physics.control_hz + 0.5);
      policy = std::make_unique<ExpertPolicy>(scenario, vec_env.model(), slots, config.expert_mode,
                                              control_hz / config.expert_hz);
    } else {
      policy =
          MakeBuiltinPolicy(config.policy, scenario, vec_env.model(), slots, config.actions_file, config.expert_mode);
    }
  }
  const std::vector<std::string> cameras = CamerasToRender(*policy, config);
  if (!cameras.empty()) {
    vec_env.EnableCameras({cameras, result.render_width, result.render_height, false, false});
    vec_env.BlockCameras(ProtocolBlackCameras(config.camera));
  }

  const RecordSettings record_settings =
      RecordSettingsFor(config, policy->control_ticks_per_action(), vec_env.model().physics, served != nullptr);
  result.galt_fps = record_settings.galt_fps;
  result.galt_policy_rate_fps = record_settings.policy_rate_fps;
  EpisodeRecorder recorder(slots, vec_env.model().physics.max_control_steps(), record_settings, config.first_episode,
                           [&](EpisodeRecord&& record) {
                             if (on_record) on_record(record);
                             result.successes += record.success ? 1 : 0;
                             result.episodes.push_back(std::move(record));
                           });
  if (config.first_episode < end_episode) {
    EpisodeDriver driver(vec_env, *policy, end_episode - config.first_episode, config.first_episode);
    // The caller's sinks hear of an episode's end before the recorder hands its record on.
    if (sinks) {
      for (EpisodeSink* sink : sinks(vec_env, ProtocolCameras(policy->cameras(), config.camera))) driver.AddSink(*sink);
    }
    driver.AddSink(recorder);
    driver.SetProgress(progress);
    driver.SetCameraProtocol(config.camera);
    if (config.profile) driver.EnableProfile();
    result.per_slot = driver.schedule() == EpisodeDriver::Schedule::kPerSlot;
    driver.Run();
    result.control_ticks = driver.control_ticks();
    if (config.profile) result.profile = driver.profile();
  }

  result.rendered_cameras = cameras;
  result.envs = slots;
  result.rendered_images = vec_env.rendered_images();
  if (served != nullptr) {
    result.requests = served->timings();
    result.server_metadata = served->server_metadata();
  }
  result.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace tavis::batch::cell

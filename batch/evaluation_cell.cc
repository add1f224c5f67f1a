#include "batch/evaluation_cell.h"

#include <algorithm>
#include <chrono>
#include <sstream>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "batch/builtin_policies.h"
#include "batch/vec_env.h"
#include "configs/robot_config.h"
#include "scenarios/registry.h"

namespace tavis::batch {
namespace {

void ValidateConfig(const EvaluationCellConfig& config) {
  if (config.episodes < 1) throw std::invalid_argument("--episodes must be at least 1, got " + std::to_string(config.episodes));
  if (config.envs < 1) throw std::invalid_argument("--envs must be at least 1, got " + std::to_string(config.envs));
  CheckBuiltinPolicyName(config.policy);
  CameraSettings cameras;
  cameras.cameras = config.render_cameras;
  cameras.width = config.image_width;
  cameras.height = config.image_height;
  ValidateCameraSettings(cameras);
}

// The policy's cameras first (its images keep their order), then the extra cameras to render.
std::vector<std::string> CamerasToRender(const Policy& policy, const EvaluationCellConfig& config) {
  std::vector<std::string> cameras = policy.cameras();
  for (const std::string& name : config.render_cameras) {
    if (std::find(cameras.begin(), cameras.end(), name) == cameras.end()) cameras.push_back(name);
  }
  return cameras;
}

// GALT over the successful episodes' commanded actions, one sample every `stride` control ticks,
// written to `slot` of each record.
void ComputeGalt(CellResult& result, int stride, double fps, std::optional<kinematics::GaltResult> EpisodeRecord::*slot) {
  std::vector<kinematics::TrajectoryView> views;
  std::vector<EpisodeRecord*> successful;
  for (EpisodeRecord& record : result.episodes) {
    if (!record.success || record.actions.empty()) continue;
    const int samples = (static_cast<int>(record.actions.size()) + stride - 1) / stride;
    views.push_back({record.actions.front().data(), samples, kinematics::action::kSize * stride});
    successful.push_back(&record);
  }
  const std::vector<kinematics::GaltResult> galt = kinematics::ComputeGaltBatch(views, fps);
  for (size_t i = 0; i < successful.size(); ++i) successful[i]->*slot = galt[i];
}

// GALT sampled when the policy acted (every `hold_ticks` control ticks), as the reference records
// actions at its policy rate; for a policy acting faster, also at the 20 Hz policy rate.
void AddGalt(CellResult& result, int hold_ticks, const engine::PhysicsSettings& physics) {
  result.galt_fps = physics.control_hz / hold_ticks;
  ComputeGalt(result, hold_ticks, result.galt_fps, &EpisodeRecord::galt);
  const int policy_stride = physics.controls_per_policy();
  if (hold_ticks < policy_stride) {
    result.galt_policy_rate_fps = physics.control_hz / policy_stride;
    ComputeGalt(result, policy_stride, result.galt_policy_rate_fps, &EpisodeRecord::galt_policy_rate);
  }
}

}  // namespace

bool EpisodeDealer::Deal(VecEnv& env, int slot) {
  if (next_ >= total_) {
    env.Release(slot);
    return false;
  }
  env.ResetEnv(slot, next_++);
  return true;
}

CellResult RunEvaluationCell(const EvaluationCellConfig& config, const ProgressCallback& progress) {
  ValidateConfig(config);
  const scenarios::ScenarioDef& scenario = scenarios::FindScenario(config.task);
  const kinematics::RobotModel robot = configs::LoadRobotModel(configs::RobotConfigPath(config.config_dir, config.robot));
  const auto start = std::chrono::steady_clock::now();

  const int slots = std::min(config.envs, config.episodes);
  VecEnv env(BuildWorldModel(robot, scenario), scenario, config.split, slots, config.seed);
  std::unique_ptr<Policy> policy = MakeBuiltinPolicy(config.policy, scenario, env.model(), slots, config.actions_file);
  const int hold_ticks = policy->control_ticks_per_action();
  const int ticks_per_policy_step = env.model().physics.controls_per_policy();
  const std::vector<std::string> cameras = CamerasToRender(*policy, config);
  if (!policy->cameras().empty() && hold_ticks % ticks_per_policy_step != 0) {
    throw std::invalid_argument("policy '" + policy->name() + "' uses cameras but acts every " +
                                std::to_string(hold_ticks) + " control ticks; it must act on policy ticks (a multiple of " +
                                std::to_string(ticks_per_policy_step) + "), where its images are rendered");
  }
  if (!cameras.empty()) env.EnableCameras({cameras, config.image_width, config.image_height, false, false});

  CellResult result;
  result.config = config;
  result.rendered_cameras = cameras;
  result.episodes.resize(config.episodes);
  std::vector<kinematics::Action> actions(slots);
  std::vector<std::vector<kinematics::Action>> action_logs(slots);
  for (auto& log : action_logs) log.reserve(env.model().physics.max_control_steps());

  EpisodeDealer dealer(config.episodes);
  auto start_episode = [&](int slot) {
    if (!dealer.Deal(env, slot)) return;
    policy->Reset(env.model(), env.state(), slot);
    action_logs[slot].clear();
  };
  for (int slot = 0; slot < slots; ++slot) start_episode(slot);

  int finished = 0;
  while (finished < config.episodes) {
    const engine::BatchState& state = env.state();
    const Observation observation = env.Observe();  // renders only if cameras are enabled
    tbb::parallel_for(0, slots, [&](int slot) {
      if (state.episode[slot] < 0) return;
      if (state.control_step[slot] % hold_ticks == 0) policy->Act(env.model(), observation, slot, actions[slot]);
      action_logs[slot].push_back(actions[slot]);
    });
    env.Step(actions);
    result.control_ticks += std::count_if(state.episode.begin(), state.episode.end(), [](int64_t e) { return e >= 0; });
    // Serial, in slot order: finished episodes are recorded and slots refilled deterministically.
    for (int slot = 0; slot < slots; ++slot) {
      if (state.episode[slot] < 0 || state.end[slot] == engine::EpisodeEnd::kRunning) continue;
      if (state.end[slot] == engine::EpisodeEnd::kInvalidAction) {
        std::ostringstream message;
        message << "policy '" << config.policy << "' produced a non-finite action in episode " << state.episode[slot]
                << ": entry " << env.invalid_action_index(slot) << " = " << env.invalid_action_value(slot);
        throw std::runtime_error(message.str());
      }
      EpisodeRecord& record = result.episodes[state.episode[slot]];
      record.episode = state.episode[slot];
      record.end = state.end[slot];
      record.success = state.end[slot] == engine::EpisodeEnd::kSuccess;
      record.length_control_ticks = state.control_step[slot];
      record.length_steps = (state.control_step[slot] + ticks_per_policy_step - 1) / ticks_per_policy_step;
      record.solver_messages = env.solver_messages(slot);
      record.actions = action_logs[slot];
      result.successes += record.success ? 1 : 0;
      ++finished;
      if (progress) progress(finished, config.episodes);
      start_episode(slot);
    }
  }
  AddGalt(result, hold_ticks, env.model().physics);
  result.rendered_images = env.rendered_images();
  result.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace tavis::batch

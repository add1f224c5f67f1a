#include "batch/cell/evaluation_cell.h"

#include <algorithm>
#include <chrono>
#include <memory>

#include "batch/builtin_policies.h"
#include "batch/cell/cell_profiler.h"
#include "batch/cell/episode_timer.h"
#include "batch/policy_kinds.h"
#include "batch/vec_env.h"
#include "kinematics/invariant.h"

namespace tavis::batch::cell {
namespace {

remote::RemotePolicyOptions ServedOptions(const CellPlan& plan) {
  const EvaluationCellConfig& config = plan.config;
  remote::RemotePolicyOptions options;
  options.servers = config.servers;
  options.replan_steps = config.replan_steps;
  options.mode = config.serving;
  options.keys = *plan.keys;
  options.protocol = config.camera;
  options.ready_timeout = std::chrono::milliseconds(static_cast<int64_t>(config.server_ready_timeout_s * 1000.0));
  options.reply_timeout = std::chrono::milliseconds(static_cast<int64_t>(config.reply_timeout_s * 1000.0));
  options.max_reply_bytes = static_cast<std::uint64_t>(config.max_reply_mb * 1024.0 * 1024.0);
  options.state_size = static_cast<int>(plan.model.robot.observation_state.size());
  options.task = config.task;
  options.robot = config.robot;
  return options;
}

std::unique_ptr<Policy> MakeCellPolicy(const CellPlan& plan, const VecEnv& vec_env, int slots) {
  const EvaluationCellConfig& config = plan.config;
  if (plan.policy == PolicyKind::kOpenpi) return std::make_unique<remote::RemotePolicy>(ServedOptions(plan), slots);
  if (plan.policy == PolicyKind::kExpert) {
    const int control_hz = static_cast<int>(vec_env.model().physics.control_hz + 0.5);
    return std::make_unique<ExpertPolicy>(*plan.scenario, vec_env.model(), slots, config.expert_mode,
                                          control_hz / config.expert_hz);
  }
  return MakeBuiltinPolicy(config.policy, *plan.scenario, vec_env.model(), slots, config.actions_file,
                           config.expert_mode);
}

// The result's settings and what the plan resolved, before any episode has run.
CellResult PlannedResult(const CellPlan& plan, int slots) {
  CellResult result;
  result.config = plan.config;
  result.config.image_width = plan.image_width;
  result.config.image_height = plan.image_height;
  result.render_width = plan.render_width;
  result.render_height = plan.render_height;
  result.galt_fps = plan.record.galt_fps;
  result.galt_policy_rate_fps = plan.record.policy_rate_fps;
  result.rendered_cameras = plan.cameras;
  result.envs = slots;
  if (plan.keys) result.observation_keys_source = plan.keys->source;
  result.layout_differences = plan.layout_differences;
  return result;
}

}  // namespace

std::string CellPolicyNames() { return PolicyNames(/*built_in_only=*/false); }

bool RunsPerSlot(const EvaluationCellConfig& config) { return !IsPolicy(config.policy, PolicyKind::kOpenpi); }

int DefaultEnvs(const std::string& policy, int threads) {
  constexpr int kDefaultEnvs = 32;
  constexpr int kServedEnvsPerThread = 6;
  return IsPolicy(policy, PolicyKind::kOpenpi) ? std::max(kDefaultEnvs, kServedEnvsPerThread * threads) : kDefaultEnvs;
}

CellResult RunEvaluationCell(const EvaluationCellConfig& config, const ProgressCallback& progress,
                             const RecordCallback& on_record, const CellSinks& sinks) {
  return RunEvaluationCell(PlanCell(config), progress, on_record, sinks);
}

CellResult RunEvaluationCell(const CellPlan& plan, const ProgressCallback& progress, const RecordCallback& on_record,
                             const CellSinks& sinks) {
  const EvaluationCellConfig& config = plan.config;
  const auto start = std::chrono::steady_clock::now();
  const int64_t end_episode = plan.end_episode();
  const int slots = static_cast<int>(std::clamp<int64_t>(end_episode - config.first_episode, 1, config.envs));
  VecEnv vec_env(plan.model, *plan.scenario, config.split, slots, config.seed);
  CellResult result = PlannedResult(plan, slots);
  const std::unique_ptr<Policy> policy = MakeCellPolicy(plan, vec_env, slots);
  // The plan decided the cameras and the records from the policy's kind; the policy must agree.
  TAVIS_INVARIANT(policy->control_ticks_per_action() == plan.control_ticks_per_action,
                  "the policy holds its actions as long as the plan says");
  TAVIS_INVARIANT(ProtocolCameras(policy->cameras(), config.camera) == plan.policy_cameras,
                  "the policy sees the cameras the plan says");
  if (!plan.cameras.empty()) {
    vec_env.EnableCameras({plan.cameras, plan.render_width, plan.render_height, false, false});
    vec_env.BlockCameras(ProtocolBlackCameras(config.camera));
  }
  EpisodeTimer timer;
  EpisodeRecorder recorder(slots, vec_env.model().physics.max_control_steps(), plan.record, config.first_episode,
                           [&](EpisodeRecord&& record) {
                             // The episode has ended (the timer has its times) before its record is made.
                             record.times = timer.Take(record.episode);
                             if (on_record) on_record(record);
                             result.successes += record.success ? 1 : 0;
                             result.episodes.push_back(std::move(record));
                           });
  if (config.first_episode < end_episode) {
    EpisodeDriver driver(vec_env, *policy, end_episode - config.first_episode, config.first_episode);
    // The caller's sinks hear of an episode's end before the recorder hands its record on.
    if (sinks) {
      for (EpisodeSink* sink : sinks(vec_env, plan.policy_cameras)) driver.AddSink(*sink);
    }
    driver.AddSink(recorder);
    driver.SetProgress(progress);
    driver.SetCameraProtocol(config.camera);
    // Every cell times its episodes; with `profile` the profiler observes the loop too.
    CellProfiler profiler;
    LoopObservers observers;
    observers.Add(timer);
    if (config.profile) observers.Add(profiler);
    driver.SetObserver(observers);
    result.per_slot = driver.schedule() == EpisodeDriver::Schedule::kPerSlot;
    driver.Run();
    result.control_ticks = driver.control_ticks();
    if (config.profile) result.profile = profiler.profile();
  }
  result.rendered_images = vec_env.rendered_images();
  if (const auto* served = dynamic_cast<const remote::RemotePolicy*>(policy.get())) {
    result.requests = served->timings();
    result.server_metadata = served->server_metadata();
  }
  result.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace tavis::batch::cell

#include "batch/cell/cell_profiler.h"

#include <algorithm>
#include <array>

#include "batch/policy.h"
#include "batch/usable_threads.h"
#include "batch/vec_env.h"

namespace tavis::batch::cell {

double CellProfiler::SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

void CellProfiler::RunStarting(VecEnv& vec_env, Policy& policy, bool per_slot) {
  run_start_ = Clock::now();
  const int slots = vec_env.num_envs();
  vec_env_ = &vec_env;
  vec_env.EnableStageTiming(true);
  timed_policy_ = dynamic_cast<PerEnvPolicy*>(&policy);
  if (timed_policy_ != nullptr) timed_policy_->EnableEnvTiming(true, slots);
  profile_ = CellProfile();
  profile_.per_slot = per_slot;
  part_start_.assign(static_cast<std::size_t>(slots) + 1, run_start_);
  parallel_seconds_ = recording_seconds_ = policy_seconds_ = reset_seconds_ = 0.0;
  episode_seconds_.assign(slots, 0.0);
  all_slots_.assign(slots, 1);
  slot_reset_seconds_.assign(slots, 0.0);
  slot_recording_seconds_.assign(slots, 0.0);
}

void CellProfiler::PartStarting(LoopPart, int slot) { part_start_[static_cast<std::size_t>(slot + 1)] = Clock::now(); }

void CellProfiler::PartEnded(LoopPart part, int slot) {
  const bool sinks = part == LoopPart::kSinks || part == LoopPart::kVideo;
  // A slot's own parts but its sinks run inside the per-slot workers' part (kParallel of the
  // batch); their costs are timed env by env (VecEnv's and the policy's env timing).
  if (slot >= 0 && !sinks) return;
  const double seconds = SecondsSince(part_start_[static_cast<std::size_t>(slot + 1)]);
  if (sinks) {
    // Per slot a worker's sinks run inside the parallel section and count in its episode's
    // recording, added when the episode ends (slots' parts may run concurrently).
    if (profile_.per_slot && slot >= 0) {
      slot_recording_seconds_[static_cast<std::size_t>(slot)] += seconds;
    } else {
      recording_seconds_ += seconds;
    }
    return;
  }
  // Every other part of the batch runs spread over the threads.
  parallel_seconds_ += seconds;
  // A policy that times its envs is counted env by env (EndSection), its resets included.
  if (part == LoopPart::kPolicyActs && timed_policy_ == nullptr) policy_seconds_ += seconds;
}

double CellProfiler::EndSection(const std::vector<uint8_t>& slots) {
  double slowest = 0.0, work = 0.0, env_work = 0.0;
  for (int slot = 0; slot < vec_env_->num_envs(); ++slot) {
    if (!slots[slot]) continue;
    const double policy = timed_policy_ != nullptr ? timed_policy_->TakeEnvSeconds(slot) : 0.0;
    const double env_cost = vec_env_->TakeEnvSeconds(slot);
    const double cost = env_cost + policy;
    env_work += env_cost;
    policy_seconds_ += policy;
    episode_seconds_[slot] += cost;
    slowest = std::max(slowest, cost);
    work += cost;
  }
  profile_.slowest_env_seconds += slowest;
  profile_.sections.emplace_back(slowest, work);
  return env_work;
}

void CellProfiler::EpisodesStarted(const std::vector<uint8_t>& started) { reset_seconds_ += EndSection(started); }

void CellProfiler::TickEnded() { EndSection(all_slots_); }

void CellProfiler::EnvReset(int slot) { slot_reset_seconds_[slot] += vec_env_->TakeEnvSeconds(slot); }

void CellProfiler::EpisodeEnding(int slot) {
  const engine::BatchState& state = vec_env_->state();
  double cost = episode_seconds_[slot];
  if (profile_.per_slot) {
    const double policy = timed_policy_->TakeEnvSeconds(slot);
    cost = vec_env_->TakeEnvSeconds(slot) + slot_reset_seconds_[slot] + policy;
    reset_seconds_ += slot_reset_seconds_[slot];
    policy_seconds_ += policy;
  }
  profile_.episodes.push_back({state.episode[slot], slot, state.control_step[slot], cost});
  episode_seconds_[slot] = 0.0;
  end_start_ = Clock::now();
}

void CellProfiler::EpisodeEnded(int slot) {
  const double seconds = SecondsSince(end_start_);
  recording_seconds_ += seconds;
  if (!profile_.per_slot) return;
  // The ends are serialised: on unlimited threads they would still run one at a time.
  profile_.serial_seconds += seconds;
  recording_seconds_ += slot_recording_seconds_[slot];
  slot_reset_seconds_[slot] = 0.0;
  slot_recording_seconds_[slot] = 0.0;
}

void CellProfiler::RunEnded() {
  const double wall_seconds = SecondsSince(run_start_);
  const int threads = UsableThreads();
  const std::array<double, kNumStages> stage = vec_env_->stage_seconds();
  profile_.threads = threads;
  profile_.wall_seconds = wall_seconds;
  const double outside_parallel = std::max(0.0, wall_seconds - parallel_seconds_);
  profile_.serial_seconds += outside_parallel;
  const VecEnv::RenderTimes render = vec_env_->render_times();
  profile_.render_wall_seconds = stage[static_cast<int>(Stage::kRender)];
  profile_.render_cpu_seconds = render.cpu;
  profile_.render_idle_seconds = std::max(0.0, render.held - render.cpu);
  // Lock-step render calls hold every thread; per slot they are part of their episodes' costs.
  profile_.render_seconds = profile_.per_slot ? 0.0 : render.held;
  profile_.stages.clear();
  for (Stage name :
       {Stage::kApplyActions, Stage::kStepPhysics, Stage::kServoNeck, Stage::kUpdateTask, Stage::kEndEpisodes}) {
    profile_.stages.emplace_back(ToString(name), stage[static_cast<int>(name)]);
  }
  profile_.stages.emplace_back(ToString(Stage::kReset), reset_seconds_);
  profile_.stages.emplace_back(ToString(Stage::kRender), profile_.render_cpu_seconds);
  // Lock-step render calls hold every thread: their idle time is the cell's. Per slot the other
  // threads go on working; a call's wall time beyond its CPU time is the machine preempting it,
  // reported apart (render_idle_seconds) but no work.
  if (!profile_.per_slot) profile_.stages.emplace_back("render_idle", profile_.render_idle_seconds);
  profile_.stages.emplace_back("policy", policy_seconds_);
  profile_.stages.emplace_back("recording", recording_seconds_);
  // Lock-step sinks run outside the parallel sections, per-slot ones inside them.
  profile_.stages.emplace_back(
      "driver", profile_.per_slot ? outside_parallel : std::max(0.0, outside_parallel - recording_seconds_));
}

}  // namespace tavis::batch::cell

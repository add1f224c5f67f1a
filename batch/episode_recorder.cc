#include "batch/episode_recorder.h"

namespace tavis::batch {

EpisodeRecorder::EpisodeRecorder(int64_t episodes, int slots, int max_control_steps)
    : records_(static_cast<std::size_t>(episodes)), action_logs_(static_cast<std::size_t>(slots)) {
  for (auto& log : action_logs_) log.reserve(static_cast<std::size_t>(max_control_steps));
}

void EpisodeRecorder::EpisodeStarted(const VecEnv&, int slot) { action_logs_[slot].clear(); }

void EpisodeRecorder::ActionsChosen(const VecEnv& env, const ActionBatch& actions) {
  const engine::BatchState& state = env.state();
  for (int slot = 0; slot < state.num_envs; ++slot) {
    if (state.running(slot)) action_logs_[slot].push_back(actions[slot]);
  }
}

void EpisodeRecorder::EpisodeEnded(const VecEnv& env, int slot) {
  const engine::BatchState& state = env.state();
  const int ticks_per_policy_step = env.model().physics.controls_per_policy();
  EpisodeRecord& record = records_[static_cast<std::size_t>(state.episode[slot])];
  record.episode = state.episode[slot];
  record.end = state.end[slot];
  record.success = state.end[slot] == engine::EpisodeEnd::kSuccess;
  record.length_control_ticks = state.control_step[slot];
  record.length_steps = (state.control_step[slot] + ticks_per_policy_step - 1) / ticks_per_policy_step;
  record.solver_messages = env.solver_messages(slot);
  record.invalid_action = state.invalid_action[slot];
  record.actions = action_logs_[slot];
  successes_ += record.success ? 1 : 0;
}

}  // namespace tavis::batch

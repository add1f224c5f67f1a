#include "batch/episode_driver.h"

#include <stdexcept>
#include <string>

namespace tavis::batch {

EpisodeDriver::EpisodeDriver(VecEnv& env, Policy& policy, int64_t episodes, int64_t first_episode)
    : env_(env),
      policy_(policy),
      total_(episodes),
      end_episode_(first_episode + episodes),
      next_episode_(first_episode),
      proprioception_(env.model().robot, env.num_envs()) {
  if (episodes < 1) throw std::invalid_argument("--episodes must be at least 1, got " + std::to_string(episodes));
  if (first_episode < 0) throw std::invalid_argument("the first episode index must be >= 0, got " + std::to_string(first_episode));
  const std::size_t slots = static_cast<std::size_t>(env.num_envs());
  prompts_.assign(slots, nullptr);
  acting_.assign(slots, 0);
  observed_.assign(slots, 0);
  started_.assign(slots, 0);
  starts_.reserve(slots);
  actions_.assign(slots, kinematics::Action{});
}

Observation EpisodeDriver::MakeObservation() const {
  return Observation{env_.model(), env_.state(), env_.images(), prompts_, &proprioception_};
}

void EpisodeDriver::Run() {
  const int hold_ticks = policy_.control_ticks_per_action();
  const int ticks_per_policy_step = env_.model().physics.controls_per_policy();
  if (!policy_.cameras().empty() && hold_ticks % ticks_per_policy_step != 0) {
    throw std::invalid_argument("policy '" + policy_.name() + "' uses cameras but acts every " +
                                std::to_string(hold_ticks) + " control ticks; it must act on policy ticks (a multiple of " +
                                std::to_string(ticks_per_policy_step) + "), where its images are rendered");
  }
  const engine::BatchState& state = env_.state();
  const int slots = env_.num_envs();
  while (true) {
    CollectAndRefill();
    if (finished_ >= total_) break;
    for (EpisodeSink* sink : sinks_) sink->TickStarting(env_);
    env_.RenderPolicyTick();
    int running = 0;
    for (int slot = 0; slot < slots; ++slot) {
      acting_[slot] = state.running(slot) && state.control_step[slot] % hold_ticks == 0;
      observed_[slot] = acting_[slot] && state.control_step[slot] % ticks_per_policy_step == 0;
      running += state.running(slot) ? 1 : 0;
    }
    proprioception_.Update(state, observed_);
    policy_.Act(MakeObservation(), acting_, actions_);
    faults_.clear();
    policy_.TakeFaults(faults_);
    for (PolicyFault& fault : faults_) env_.EndInvalid(fault.env, {-1, 0.0, std::move(fault.reason)});
    for (ActionBatch::value_type& action : actions_) ApplyToAction(protocol_, action);
    for (EpisodeSink* sink : sinks_) sink->ActionsChosen(env_, actions_);
    env_.Step(actions_);
    control_ticks_ += running;
    for (EpisodeSink* sink : sinks_) sink->Stepped(env_);
  }
}

void EpisodeDriver::CollectAndRefill() {
  const engine::BatchState& state = env_.state();
  const int slots = env_.num_envs();
  starts_.clear();
  for (int slot = 0; slot < slots; ++slot) {
    started_[slot] = 0;
    if (state.episode[slot] < 0) {
      // Idle: not dealt yet (a slot is released only once no episode is left).
      if (next_episode_ < end_episode_) starts_.push_back({slot, next_episode_++});
      continue;
    }
    if (state.running(slot)) {
      bool complete = false;
      for (const EpisodeSink* sink : sinks_) complete = complete || sink->EpisodeComplete(env_, slot);
      if (!complete) continue;
      env_.Stop(slot);
    }
    for (EpisodeSink* sink : sinks_) sink->EpisodeEnded(env_, slot);
    ++finished_;
    if (progress_) progress_(finished_, total_);
    prompts_[slot] = nullptr;
    if (next_episode_ < end_episode_) {
      starts_.push_back({slot, next_episode_++});
    } else {
      env_.Release(slot);
    }
  }
  if (starts_.empty()) return;
  env_.Reset(starts_);
  for (const EpisodeStart& start : starts_) {
    started_[start.env] = 1;
    prompts_[start.env] = env_.scenario().prompt(state, start.env);
  }
  policy_.Reset(MakeObservation(), started_);
  for (const EpisodeStart& start : starts_) {
    for (EpisodeSink* sink : sinks_) sink->EpisodeStarted(env_, start.env);
  }
}

}  // namespace tavis::batch

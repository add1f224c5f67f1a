#include "batch/episode_driver.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include "batch/usable_threads.h"

namespace tavis::batch {

EpisodeDriver::EpisodeDriver(VecEnv& vec_env, Policy& policy, int64_t episodes, int64_t first_episode)
    : vec_env_(vec_env),
      policy_(policy),
      slots_(vec_env),
      ticker_(slots_),
      total_(episodes),
      end_episode_(first_episode + episodes),
      next_episode_(first_episode) {
  if (episodes < 1) throw std::invalid_argument("episodes must be at least 1, got " + std::to_string(episodes));
  if (first_episode < 0)
    throw std::invalid_argument("the first episode index must be >= 0, got " + std::to_string(first_episode));
  const std::size_t slots = static_cast<std::size_t>(vec_env.num_envs());
  acting_.assign(slots, 0);
  observed_.assign(slots, 0);
  starts_.reserve(slots);
  actions_.assign(slots, kinematics::Action{});
  ticker_.AddPolicy(policy);
}

EpisodeDriver::Schedule EpisodeDriver::schedule() const {
  if (lock_step_required_ || dynamic_cast<PerEnvPolicy*>(&policy_) == nullptr) {
    return Schedule::kLockStep;
  }
  for (const EpisodeSink* sink : slots_.sinks()) {
    if (!sink->works_per_slot()) return Schedule::kLockStep;
  }
  return Schedule::kPerSlot;
}

void EpisodeDriver::Run() {
  const int hold_ticks = policy_.control_ticks_per_action();
  const int ticks_per_policy_step = vec_env_.model().physics.controls_per_policy();
  if (!policy_.cameras().empty() && hold_ticks % ticks_per_policy_step != 0) {
    throw std::invalid_argument("policy '" + policy_.name() + "' uses cameras but acts every " +
                                std::to_string(hold_ticks) +
                                " control ticks; it must act on policy ticks (a multiple of " +
                                std::to_string(ticks_per_policy_step) + "), where its images are rendered");
  }
  const Schedule chosen = schedule();
  // The run starts now: a progress rate counts from here, not from the first episode to end (the
  // slots of a lock-step run end their first episodes together, and a rate timed from the first
  // of them divides a batch by microseconds).
  if (progress_) progress_(finished_, total_);
  LoopObserver* observer = slots_.observer();
  if (observer != nullptr) observer->RunStarting(vec_env_, policy_, chosen == Schedule::kPerSlot);
  if (chosen == Schedule::kPerSlot) {
    RunPerSlot(*dynamic_cast<PerEnvPolicy*>(&policy_));
  } else {
    RunLockStep();
  }
  if (observer != nullptr) observer->RunEnded();
}

void EpisodeDriver::Finished() {
  ++finished_;
  if (progress_) progress_(finished_, total_);
}

void EpisodeDriver::RunLockStep() {
  for (int64_t tick = 0;; ++tick) {
    CollectAndRefill(tick);
    if (finished_ >= total_) break;
    ticker_.TickStarting();
    ticker_.RenderPolicyTick();
    Act();
    ticker_.Tick(actions_, &policy_);
  }
}

void EpisodeDriver::Act() {
  const int hold_ticks = policy_.control_ticks_per_action();
  const int ticks_per_policy_step = vec_env_.model().physics.controls_per_policy();
  const engine::BatchState& state = vec_env_.state();
  for (int slot = 0; slot < vec_env_.num_envs(); ++slot) {
    acting_[slot] = state.running(slot) && state.control_step[slot] % hold_ticks == 0;
    observed_[slot] = acting_[slot] && state.control_step[slot] % ticks_per_policy_step == 0;
  }
  slots_.proprioception().Update(state, observed_);
  Observe(slots_.observer(), LoopPart::kPolicyActs, kWholeBatch,
          [&] { policy_.Act(slots_.observation(), acting_, actions_); });
}

void EpisodeDriver::CollectAndRefill(int64_t tick) {
  ticker_.CollectEnded([&](int) { Finished(); });
  const engine::BatchState& state = vec_env_.state();
  // With cameras, episodes start only on ticks where the running ones are at a policy tick, so
  // that every render call draws all of them (rather than a third of them on every tick).
  const bool deal_now = vec_env_.renderer() == nullptr || tick % vec_env_.model().physics.controls_per_policy() == 0;
  starts_.clear();
  for (int slot = 0; slot < vec_env_.num_envs(); ++slot) {
    if (state.running(slot)) continue;
    if (deal_now && next_episode_ < end_episode_) {
      starts_.push_back({slot, next_episode_++});
    } else if (state.episode[slot] >= 0) {
      slots_.Release(slot);  // ended, and nothing to deal now: idle until a deal
    }
  }
  ticker_.StartEpisodes(starts_);
}

void EpisodeDriver::RunPerSlot(PerEnvPolicy& policy) {
  // One worker per thread, each on its own slot: the slots beyond the threads stay idle.
  const int workers = std::min(vec_env_.num_envs(), UsableThreads());
  Observe(slots_.observer(), LoopPart::kParallel, kWholeBatch, [&] {
    tbb::parallel_for(
        0, workers, 1, [&](int slot) { RunSlot(policy, slot); }, tbb::simple_partitioner());
  });
}

int64_t EpisodeDriver::DealNext() {
  std::lock_guard<std::mutex> lock(deal_mutex_);
  return next_episode_ < end_episode_ && !stopping_ ? next_episode_++ : -1;
}

void EpisodeDriver::RunSlot(PerEnvPolicy& policy, int slot) {
  try {
    for (int64_t episode = DealNext(); episode >= 0; episode = DealNext()) RunSlotEpisode(policy, slot, episode);
    slots_.Release(slot);
  } catch (...) {
    // The other workers stop at their next deal rather than run the cell to its end.
    stopping_ = true;
    throw;
  }
}

void EpisodeDriver::RunSlotEpisode(PerEnvPolicy& policy, int slot, int64_t episode) {
  const int hold_ticks = policy.control_ticks_per_action();
  const int ticks_per_policy_step = vec_env_.model().physics.controls_per_policy();
  const engine::BatchState& state = vec_env_.state();
  const Observation observation = slots_.observation();
  kinematics::Action& action = actions_[slot];
  LoopObserver* observer = slots_.observer();
  Observe(observer, LoopPart::kReset, slot, [&] { vec_env_.ResetEnv(slot, episode); });
  if (observer != nullptr) observer->EnvReset(slot);
  slots_.EpisodeReset(slot);
  Observe(observer, LoopPart::kPolicyResets, slot, [&] { policy.ResetOne(observation, slot); });
  slots_.TellSinks(slot, [&](EpisodeSink& sink) { sink.EpisodeStarted(vec_env_, slot); });
  int64_t ticks = 0;
  while (state.running(slot) && !slots_.StopIfSinksAreDone(slot)) {
    slots_.TellSinks(slot, [&](EpisodeSink& sink) { sink.SlotTickStarting(vec_env_, slot); });
    // The slot's cameras at its own policy ticks, as RenderPolicyTick draws them for the batch
    // (observed only where there are cameras and it is a policy tick: a tick's clock reads are few).
    const bool policy_tick = state.control_step[slot] % ticks_per_policy_step == 0;
    if (vec_env_.renderer() != nullptr && policy_tick) {
      Observe(observer, LoopPart::kRender, slot, [&] { vec_env_.RenderEnvPolicyTick(slot); });
    }
    if (state.control_step[slot] % hold_ticks == 0) {
      if (policy_tick) slots_.proprioception().UpdateEnv(state, slot);
      Observe(observer, LoopPart::kPolicyActs, slot, [&] { policy.ActOne(observation, slot, action); });
    }
    slots_.ActionChosen(slot, action);
    Observe(observer, LoopPart::kStep, slot, [&] { vec_env_.StepEnv(slot, actions_); });
    slots_.EndIfGaveUp(policy, slot);
    slots_.TellSinks(slot, [&](EpisodeSink& sink) { sink.SlotStepped(vec_env_, slot); });
    ++ticks;
  }
  FinishSlotEpisode(slot, ticks);
}

void EpisodeDriver::FinishSlotEpisode(int slot, int64_t ticks) {
  std::lock_guard<std::mutex> lock(finish_mutex_);
  slots_.TellEnded(slot);
  per_slot_ticks_ += ticks;
  Finished();
}

}  // namespace tavis::batch

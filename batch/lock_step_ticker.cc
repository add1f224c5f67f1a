#include "batch/lock_step_ticker.h"

#include <algorithm>
#include <utility>

namespace tavis::batch {

LockStepTicker::LockStepTicker(EpisodeSlots& slots)
    : slots_(slots), vec_env_(slots.vec_env()), started_(static_cast<std::size_t>(vec_env_.num_envs()), 0) {}

void LockStepTicker::StartEpisodes(const std::vector<EpisodeStart>& starts) {
  if (starts.empty()) return;
  LoopObserver* observer = slots_.observer();
  std::fill(started_.begin(), started_.end(), 0);
  for (const EpisodeStart& start : starts) started_[static_cast<std::size_t>(start.env)] = 1;
  if (observer != nullptr) observer->EpisodesStarting(started_);
  Observe(observer, LoopPart::kReset, kWholeBatch, [&] { vec_env_.Reset(starts); });
  for (const EpisodeStart& start : starts) slots_.EpisodeReset(start.env);
  for (Policy* policy : policies_) {
    Observe(observer, LoopPart::kPolicyResets, kWholeBatch, [&] { policy->Reset(slots_.observation(), started_); });
  }
  if (observer != nullptr) observer->EpisodesStarted(started_);
  for (EpisodeSink* sink : slots_.sinks()) {
    Observe(observer, sink->timed_as(), kWholeBatch, [&] {
      for (const EpisodeStart& start : starts) sink->EpisodeStarted(vec_env_, start.env);
    });
  }
}

void LockStepTicker::TickStarting() {
  slots_.TellSinks(kWholeBatch, [&](EpisodeSink& sink) { sink.TickStarting(vec_env_); });
}

void LockStepTicker::RenderPolicyTick() {
  Observe(slots_.observer(), LoopPart::kRender, kWholeBatch, [&] { vec_env_.RenderPolicyTick(); });
}

void LockStepTicker::Tick(ActionBatch& actions, Policy* policy) {
  const engine::BatchState& state = vec_env_.state();
  const int slots = vec_env_.num_envs();
  // Counted before the policy's faults end episodes, as the ticks the policy was asked for.
  const int running = RunningEnvs();
  if (policy != nullptr) {
    faults_.clear();
    policy->TakeFaults(faults_);
    for (PolicyFault& fault : faults_) vec_env_.EndInvalid(fault.env, {-1, 0.0, std::move(fault.reason)});
  }
  for (kinematics::Action& action : actions) slots_.ApplyProtocol(action);
  for (EpisodeSink* sink : slots_.sinks()) {
    Observe(slots_.observer(), sink->timed_as(), kWholeBatch, [&] {
      for (int slot = 0; slot < slots; ++slot) {
        if (state.running(slot)) sink->ActionChosen(vec_env_, slot, actions[static_cast<std::size_t>(slot)]);
      }
    });
  }
  Observe(slots_.observer(), LoopPart::kStep, kWholeBatch, [&] { vec_env_.Step(actions); });
  if (policy != nullptr) {
    for (int slot = 0; slot < slots; ++slot) slots_.EndIfGaveUp(*policy, slot);
  }
  control_ticks_ += running;
  if (slots_.observer() != nullptr) slots_.observer()->TickEnded();
  slots_.TellSinks(kWholeBatch, [&](EpisodeSink& sink) { sink.Stepped(vec_env_); });
}

void LockStepTicker::CollectEnded(const std::function<void(int slot)>& ended) {
  const engine::BatchState& state = vec_env_.state();
  for (int slot = 0; slot < vec_env_.num_envs(); ++slot) {
    if (state.episode[slot] < 0 || slots_.told_ended(slot)) continue;
    if (state.running(slot) && !slots_.StopIfSinksAreDone(slot)) continue;
    slots_.TellEnded(slot);
    ended(slot);
  }
}

int LockStepTicker::RunningEnvs() const {
  int running = 0;
  for (int slot = 0; slot < vec_env_.num_envs(); ++slot) running += vec_env_.state().running(slot) ? 1 : 0;
  return running;
}

}  // namespace tavis::batch

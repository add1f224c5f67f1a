#include "batch/episode_driver.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

namespace tavis::batch {

EpisodeDriver::EpisodeDriver(VecEnv& env, Policy& policy, int64_t episodes, int64_t first_episode)
    : env_(env),
      policy_(policy),
      total_(episodes),
      end_episode_(first_episode + episodes),
      next_episode_(first_episode),
      proprioception_(env.model().robot, env.num_envs()) {
  if (episodes < 1) throw std::invalid_argument("--episodes must be at least 1, got " + std::to_string(episodes));
  if (first_episode < 0)
    throw std::invalid_argument("the first episode index must be >= 0, got " + std::to_string(first_episode));
  const std::size_t slots = static_cast<std::size_t>(env.num_envs());
  prompts_.assign(slots, nullptr);
  acting_.assign(slots, 0);
  observed_.assign(slots, 0);
  started_.assign(slots, 0);
  starts_.reserve(slots);
  actions_.assign(slots, kinematics::Action{});
}

template <typename Body>
double EpisodeDriver::WallSeconds(Body&& body) {
  if (!profiling_) {
    body();
    return 0.0;
  }
  const auto start = std::chrono::steady_clock::now();
  body();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double EpisodeDriver::EndSection(const std::vector<uint8_t>& slots) {
  double slowest = 0.0, work = 0.0, env_work = 0.0;
  for (int slot = 0; slot < env_.num_envs(); ++slot) {
    if (!slots[slot]) continue;
    const double policy = timed_policy_ != nullptr ? timed_policy_->TakeEnvSeconds(slot) : 0.0;
    const double env_cost = env_.TakeEnvSeconds(slot);
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

Observation EpisodeDriver::MakeObservation() const {
  return Observation{env_.model(), env_.state(), env_.images(), prompts_, &proprioception_};
}

EpisodeDriver::Schedule EpisodeDriver::schedule() const {
  if (lock_step_required_ || dynamic_cast<PerEnvPolicy*>(&policy_) == nullptr) {
    return Schedule::kLockStep;
  }
  for (const EpisodeSink* sink : sinks_) {
    if (!sink->works_per_slot()) return Schedule::kLockStep;
  }
  return Schedule::kPerSlot;
}

void EpisodeDriver::Run() {
  const int hold_ticks = policy_.control_ticks_per_action();
  const int ticks_per_policy_step = env_.model().physics.controls_per_policy();
  if (!policy_.cameras().empty() && hold_ticks % ticks_per_policy_step != 0) {
    throw std::invalid_argument("policy '" + policy_.name() + "' uses cameras but acts every " +
                                std::to_string(hold_ticks) +
                                " control ticks; it must act on policy ticks (a multiple of " +
                                std::to_string(ticks_per_policy_step) + "), where its images are rendered");
  }
  const int slots = env_.num_envs();
  const auto run_start = std::chrono::steady_clock::now();
  const Schedule chosen = schedule();
  if (profiling_) {
    env_.EnableStageTiming(true);
    timed_policy_ = dynamic_cast<PerEnvPolicy*>(&policy_);
    if (timed_policy_ != nullptr) timed_policy_->EnableEnvTiming(true, slots);
    episode_seconds_.assign(slots, 0.0);
    all_slots_.assign(slots, 1);
    profile_.per_slot = chosen == Schedule::kPerSlot;
  }
  if (chosen == Schedule::kPerSlot) {
    RunPerSlot(*dynamic_cast<PerEnvPolicy*>(&policy_));
  } else {
    RunLockStep();
  }
  if (profiling_) FinishProfile(std::chrono::duration<double>(std::chrono::steady_clock::now() - run_start).count());
}

void EpisodeDriver::RunLockStep() {
  const int hold_ticks = policy_.control_ticks_per_action();
  const int ticks_per_policy_step = env_.model().physics.controls_per_policy();
  const engine::BatchState& state = env_.state();
  const int slots = env_.num_envs();
  for (lock_step_ticks_ = 0;; ++lock_step_ticks_) {
    CollectAndRefill();
    if (finished_ >= total_) break;
    recording_seconds_ += WallSeconds([&] {
      for (EpisodeSink* sink : sinks_) sink->TickStarting(env_);
    });
    parallel_seconds_ += WallSeconds([&] { env_.RenderPolicyTick(); });
    int running = 0;
    for (int slot = 0; slot < slots; ++slot) {
      acting_[slot] = state.running(slot) && state.control_step[slot] % hold_ticks == 0;
      observed_[slot] = acting_[slot] && state.control_step[slot] % ticks_per_policy_step == 0;
      running += state.running(slot) ? 1 : 0;
    }
    proprioception_.Update(state, observed_);
    const double act_seconds = WallSeconds([&] { policy_.Act(MakeObservation(), acting_, actions_); });
    parallel_seconds_ += act_seconds;
    if (profiling_ && timed_policy_ == nullptr) policy_seconds_ += act_seconds;
    faults_.clear();
    policy_.TakeFaults(faults_);
    for (PolicyFault& fault : faults_) env_.EndInvalid(fault.env, {-1, 0.0, std::move(fault.reason)});
    for (ActionBatch::value_type& action : actions_) ApplyToAction(protocol_, action);
    recording_seconds_ += WallSeconds([&] {
      for (int slot = 0; slot < slots; ++slot) {
        if (!state.running(slot)) continue;
        for (EpisodeSink* sink : sinks_) sink->ActionChosen(env_, slot, actions_[slot]);
      }
    });
    parallel_seconds_ += WallSeconds([&] { env_.Step(actions_); });
    for (int slot = 0; slot < slots; ++slot) {
      if (state.running(slot) && policy_.GaveUp(slot)) env_.EndEarly(slot, engine::EpisodeEnd::kGaveUp);
    }
    control_ticks_ += running;
    if (profiling_) EndSection(all_slots_);
    recording_seconds_ += WallSeconds([&] {
      for (EpisodeSink* sink : sinks_) sink->Stepped(env_);
    });
  }
}

void EpisodeDriver::RunPerSlot(PerEnvPolicy& policy) {
  // One worker per thread, each on its own slot: the slots beyond the threads stay idle.
  const int workers = std::min(env_.num_envs(), tbb::this_task_arena::max_concurrency());
  parallel_seconds_ += WallSeconds([&] {
    tbb::parallel_for(
        0, workers, 1, [&](int slot) { RunSlot(policy, slot); }, tbb::simple_partitioner());
  });
}

int64_t EpisodeDriver::DealNext() {
  std::lock_guard<std::mutex> lock(deal_mutex_);
  return next_episode_ < end_episode_ && !stopping_ ? next_episode_++ : -1;
}

void EpisodeDriver::RunSlot(PerEnvPolicy& policy, int slot) {
  SlotCosts costs;
  try {
    for (int64_t episode = DealNext(); episode >= 0; episode = DealNext()) RunSlotEpisode(policy, slot, episode, costs);
    env_.Release(slot);
  } catch (...) {
    // The other workers stop at their next deal rather than run the cell to its end.
    stopping_ = true;
    throw;
  }
}

void EpisodeDriver::RunSlotEpisode(PerEnvPolicy& policy, int slot, int64_t episode, SlotCosts& costs) {
  const int hold_ticks = policy.control_ticks_per_action();
  const int ticks_per_policy_step = env_.model().physics.controls_per_policy();
  const engine::BatchState& state = env_.state();
  const Observation observation = MakeObservation();
  kinematics::Action& action = actions_[slot];
  env_.ResetEnv(slot, episode);
  if (profiling_) costs.reset += env_.TakeEnvSeconds(slot);
  prompts_[slot] = env_.prompt(slot);
  policy.ResetOne(observation, slot);
  costs.recording += WallSeconds([&] {
    for (EpisodeSink* sink : sinks_) sink->EpisodeStarted(env_, slot);
  });
  while (state.running(slot)) {
    bool complete = false;
    for (const EpisodeSink* sink : sinks_) complete = complete || sink->EpisodeComplete(env_, slot);
    if (complete) {
      env_.EndEarly(slot, engine::EpisodeEnd::kStopped);
      break;
    }
    costs.recording += WallSeconds([&] {
      for (EpisodeSink* sink : sinks_) sink->SlotTickStarting(env_, slot);
    });
    // The slot's cameras at its own policy ticks, as RenderPolicyTick draws them for the batch.
    env_.RenderEnvPolicyTick(slot);
    if (state.control_step[slot] % hold_ticks == 0) {
      if (state.control_step[slot] % ticks_per_policy_step == 0) proprioception_.UpdateEnv(state, slot);
      policy.ActOne(observation, slot, action);
      ApplyToAction(protocol_, action);
    }
    costs.recording += WallSeconds([&] {
      for (EpisodeSink* sink : sinks_) sink->ActionChosen(env_, slot, action);
    });
    env_.StepEnv(slot, actions_);
    if (state.running(slot) && policy.GaveUp(slot)) env_.EndEarly(slot, engine::EpisodeEnd::kGaveUp);
    costs.recording += WallSeconds([&] {
      for (EpisodeSink* sink : sinks_) sink->SlotStepped(env_, slot);
    });
    ++costs.control_ticks;
  }
  FinishSlotEpisode(slot, costs);
}

void EpisodeDriver::FinishSlotEpisode(int slot, SlotCosts& costs) {
  const engine::BatchState& state = env_.state();
  std::lock_guard<std::mutex> lock(finish_mutex_);
  if (profiling_) {
    const double policy = timed_policy_->TakeEnvSeconds(slot);
    const double cost = env_.TakeEnvSeconds(slot) + costs.reset + policy;
    profile_.episodes.push_back({state.episode[slot], slot, state.control_step[slot], cost});
    reset_seconds_ += costs.reset;
    policy_seconds_ += policy;
  }
  const double ended_seconds = WallSeconds([&] {
    for (EpisodeSink* sink : sinks_) sink->EpisodeEnded(env_, slot);
  });
  // The ends are serialised: on unlimited threads they would still run one at a time.
  profile_.serial_seconds += ended_seconds;
  recording_seconds_ += costs.recording + ended_seconds;
  control_ticks_ += costs.control_ticks;
  costs = SlotCosts();
  prompts_[slot] = nullptr;
  ++finished_;
  if (progress_) progress_(finished_, total_);
}

void EpisodeDriver::FinishProfile(double wall_seconds) {
  const int threads = tbb::this_task_arena::max_concurrency();
  const std::array<double, kNumStages> stage = env_.stage_seconds();
  profile_.threads = threads;
  profile_.wall_seconds = wall_seconds;
  const double outside_parallel = std::max(0.0, wall_seconds - parallel_seconds_);
  profile_.serial_seconds += outside_parallel;
  const VecEnv::RenderTimes render = env_.render_times();
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

void EpisodeDriver::CollectAndRefill() {
  const engine::BatchState& state = env_.state();
  const int slots = env_.num_envs();
  starts_.clear();
  // With cameras, episodes start only on ticks where the running ones are at a policy tick, so
  // that every render call draws all of them (rather than a third of them on every tick).
  const bool deal_now =
      env_.renderer() == nullptr || lock_step_ticks_ % env_.model().physics.controls_per_policy() == 0;
  for (int slot = 0; slot < slots; ++slot) {
    started_[slot] = 0;
    if (state.episode[slot] < 0) {
      // Idle: not dealt yet, or waiting for a policy tick to start on.
      if (deal_now && next_episode_ < end_episode_) starts_.push_back({slot, next_episode_++});
      continue;
    }
    if (state.running(slot)) {
      bool complete = false;
      for (const EpisodeSink* sink : sinks_) complete = complete || sink->EpisodeComplete(env_, slot);
      if (!complete) continue;
      env_.EndEarly(slot, engine::EpisodeEnd::kStopped);
    }
    if (profiling_) {
      profile_.episodes.push_back({state.episode[slot], slot, state.control_step[slot], episode_seconds_[slot]});
      episode_seconds_[slot] = 0.0;
    }
    recording_seconds_ += WallSeconds([&] {
      for (EpisodeSink* sink : sinks_) sink->EpisodeEnded(env_, slot);
    });
    ++finished_;
    if (progress_) progress_(finished_, total_);
    prompts_[slot] = nullptr;
    if (deal_now && next_episode_ < end_episode_) {
      starts_.push_back({slot, next_episode_++});
    } else {
      env_.Release(slot);
    }
  }
  if (starts_.empty()) return;
  parallel_seconds_ += WallSeconds([&] { env_.Reset(starts_); });
  for (const EpisodeStart& start : starts_) {
    started_[start.env] = 1;
    prompts_[start.env] = env_.prompt(start.env);
  }
  parallel_seconds_ += WallSeconds([&] { policy_.Reset(MakeObservation(), started_); });
  if (profiling_) reset_seconds_ += EndSection(started_);
  recording_seconds_ += WallSeconds([&] {
    for (const EpisodeStart& start : starts_) {
      for (EpisodeSink* sink : sinks_) sink->EpisodeStarted(env_, start.env);
    }
  });
}

}  // namespace tavis::batch

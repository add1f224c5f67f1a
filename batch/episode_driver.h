// The one episode driver: observe -> act -> step -> collect finished episodes -> refill slots.
// Everything that runs episodes uses it (evaluation cells, the visibility audit, `tavis render`;
// dataset recording and remote policies plug in as sinks and policies). What is recorded is a
// sink (batch/episode_sink.h): it is told when an episode starts, what the policy chose on every
// control tick, when the world has moved, and when the episode ends; it may end an episode early
// once it has what it needs.
//
// Two schedules, with the same results. Lock-step: every slot takes a control tick together, the
// batch's observation goes to the policy at once (a served or Python policy answers the whole
// batch), the cameras are rendered for the whole batch in one call, and finished episodes are
// collected and slots refilled in slot order; the tick itself is LockStepTicker's, which the
// Python module's env drives too. Per slot: when the policy decides each env on its own and every
// sink works per slot, each worker thread runs one slot's episodes tick after tick (the same
// per-episode pieces, EpisodeSlots), rendering the slot's cameras at its own policy ticks, and
// takes the next episode as soon as its own ends, so no env waits for the batch's slowest at every
// tick (docs/architecture.md).
//
// Episode i is always dealt with the randomness of (seed, i), whichever slot runs it, so results
// do not depend on the schedule, the thread count or the number of slots.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <vector>

#include "batch/camera_protocol.h"
#include "batch/episode_sink.h"
#include "batch/episode_slots.h"
#include "batch/lock_step_ticker.h"
#include "batch/loop_observer.h"
#include "batch/policy.h"
#include "batch/vec_env.h"

namespace tavis::batch {

// Called with (finished, total) when a run starts (0 finished) and after each finished episode.
using ProgressCallback = std::function<void(int64_t, int64_t)>;

class EpisodeDriver {
 public:
  enum class Schedule { kLockStep, kPerSlot };

  // Runs episodes first_episode .. first_episode + episodes - 1 of the env's task on its slots
  // with `policy`. Sinks and the policy must outlive Run.
  EpisodeDriver(VecEnv& vec_env, Policy& policy, int64_t episodes, int64_t first_episode = 0);

  void AddSink(EpisodeSink& sink) { slots_.AddSink(sink); }
  // Called as Run starts and after each finished episode (one call at a time, on any thread).
  void SetProgress(ProgressCallback progress) { progress_ = std::move(progress); }
  // The camera protocol's action rule, applied to every action before sinks see it and the world
  // steps with it (head by default: actions pass unchanged).
  void SetCameraProtocol(CameraProtocol protocol) { slots_.SetCameraProtocol(protocol); }
  // Runs lock-step even where the per-slot schedule applies (tests compare the two).
  void RequireLockStep() { lock_step_required_ = true; }
  // The schedule Run uses: per slot when the policy is a PerEnvPolicy, every sink
  // works_per_slot() and lock-step is not required (rendered or not); otherwise lock-step.
  Schedule schedule() const;

  // Until every episode has ended or been stopped. An unusable action (VecEnv::Step's check) or
  // a policy fault (Policy::TakeFaults) ends only its episode, as invalid_action, and a policy
  // that has given up (Policy::GaveUp) ends its episode as gave_up after the tick's step; sinks
  // see these like any other end. At policy ticks the env renders the cameras it has enabled
  // (VecEnv::EnableCameras); the caller enables the policy's. Throws std::invalid_argument if a
  // policy with cameras does not act on policy ticks; whatever the policy or a sink throws (a
  // served policy's server failing) stops the run.
  void Run();

  // Env control ticks simulated (for throughput).
  int64_t control_ticks() const { return ticker_.control_ticks() + per_slot_ticks_; }

  // Tells `observer` what the run does (LoopObserver; a cell's profiler, batch/cell/cell_profiler.h,
  // for `tavis eval --profile`); it must outlive Run. Call before Run.
  void SetObserver(LoopObserver& observer) { slots_.SetObserver(&observer); }

 private:
  void RunLockStep();
  // Lock-step: reports the slots whose episodes have ended (stopping those a sink is done
  // with), deals the next episodes to them and to idle slots in slot order (with cameras, only on
  // ticks that are policy ticks of the batch; `tick` counts the loop's ticks), and starts them.
  void CollectAndRefill(int64_t tick);
  // Lock-step: the policy's actions for the envs whose action is due.
  void Act();
  void RunPerSlot(PerEnvPolicy& policy);
  // Per slot: `slot`'s episodes one after the other until none is left to deal.
  void RunSlot(PerEnvPolicy& policy, int slot);
  void RunSlotEpisode(PerEnvPolicy& policy, int slot, int64_t episode);
  // Per slot: the next episode index, or -1 when all are dealt.
  int64_t DealNext();
  // Per slot: tells the sinks and the progress callback that `slot`'s episode has ended after
  // `ticks` control ticks; one call at a time.
  void FinishSlotEpisode(int slot, int64_t ticks);
  // Counts a finished episode and reports progress.
  void Finished();

  VecEnv& vec_env_;
  Policy& policy_;
  EpisodeSlots slots_;
  LockStepTicker ticker_;
  int64_t total_ = 0;         // episodes to run
  int64_t end_episode_ = 0;   // one past the last episode index
  int64_t next_episode_ = 0;  // the next episode index to deal
  int64_t finished_ = 0;
  int64_t per_slot_ticks_ = 0;  // control ticks of the per-slot schedule
  ProgressCallback progress_;
  bool lock_step_required_ = false;
  std::mutex deal_mutex_;              // per slot: next_episode_
  std::atomic<bool> stopping_{false};  // per slot: a worker failed
  std::mutex finish_mutex_;            // per slot: episode ends, progress and the observer's ends
  // Per-slot buffers, sized once.
  std::vector<uint8_t> acting_;
  std::vector<uint8_t> observed_;  // acting at a policy tick: proprioception is computed
  std::vector<EpisodeStart> starts_;
  ActionBatch actions_;
};

}  // namespace tavis::batch

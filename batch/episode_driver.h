// The one episode driver: observe -> act -> step -> collect finished episodes -> refill slots.
// Everything that runs episodes uses it (evaluation cells, the visibility audit, `tavis render`;
// dataset recording and remote policies plug in as sinks and policies). What is recorded is a
// sink: it is told when an episode starts, what the policy chose on every control tick, when the
// world has moved, and when the episode ends; it may end an episode early once it has what it
// needs.
//
// Two schedules, with the same results. Lock-step: every slot takes a control tick together, the
// batch's observation goes to the policy at once (a served or Python policy answers the whole
// batch), the cameras are rendered for the whole batch in one call, and finished episodes are
// collected and slots refilled in slot order. Per slot: when the policy decides each env on its
// own and every sink works per slot, each worker thread runs one slot's episodes tick after tick,
// rendering the slot's cameras at its own policy ticks, and takes the next episode as soon as its
// own ends, so no env waits for the batch's slowest at every tick (docs/architecture.md).
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
#include "batch/cell_profile.h"
#include "batch/policy.h"
#include "batch/vec_env.h"

namespace tavis::batch {

class EpisodeSink {
 public:
  virtual ~EpisodeSink() = default;
  // A control tick of the lock-step schedule is about to begin: the policy will observe the
  // state as it is now.
  virtual void TickStarting(const VecEnv& /*vec_env*/) {}
  // The slot has started episode state.episode[slot] (reset, warm-up included, and the policy reset).
  virtual void EpisodeStarted(const VecEnv& /*vec_env*/, int /*slot*/) {}
  // The action the running slot steps with on this tick (chosen now or held), before the step.
  virtual void ActionChosen(const VecEnv& /*vec_env*/, int /*slot*/, const kinematics::Action& /*action*/) {}
  // A control tick of the lock-step schedule is done.
  virtual void Stepped(const VecEnv& /*vec_env*/) {}
  // True once the sink has all it needs of the running episode in `slot`: the driver then stops
  // it (EpisodeEnd::kStopped) before the next tick. Asked before every tick.
  virtual bool EpisodeComplete(const VecEnv& /*vec_env*/, int /*slot*/) const { return false; }
  // The episode in `slot` has ended (state.end[slot] says how), before the slot is refilled.
  virtual void EpisodeEnded(const VecEnv& /*vec_env*/, int /*slot*/) {}
  // Per-slot schedule only, in place of TickStarting and Stepped: the slot's control tick is
  // about to begin (before its cameras are rendered and its policy observes it), and is done
  // (after the step, and after a policy that gave up has ended the episode).
  virtual void SlotTickStarting(const VecEnv& /*vec_env*/, int /*slot*/) {}
  virtual void SlotStepped(const VecEnv& /*vec_env*/, int /*slot*/) {}
  // True if the sink can follow slots run independently: on the per-slot schedule it is told of
  // each slot's ticks by SlotTickStarting and SlotStepped instead of TickStarting and Stepped;
  // EpisodeStarted, SlotTickStarting, ActionChosen, SlotStepped and EpisodeComplete touch only
  // their slot's data (they may run concurrently for distinct slots); and it accepts EpisodeEnded
  // calls, one at a time, in the order episodes happen to end. False: the driver runs lock-step.
  virtual bool works_per_slot() const { return false; }
};

// Called after each finished episode with (finished, total).
using ProgressCallback = std::function<void(int64_t, int64_t)>;

class EpisodeDriver {
 public:
  enum class Schedule { kLockStep, kPerSlot };

  // Runs episodes first_episode .. first_episode + episodes - 1 of the env's task on its slots
  // with `policy`. Sinks and the policy must outlive Run.
  EpisodeDriver(VecEnv& vec_env, Policy& policy, int64_t episodes, int64_t first_episode = 0);

  void AddSink(EpisodeSink& sink) { sinks_.push_back(&sink); }
  // Called after each finished episode (one call at a time, on any thread).
  void SetProgress(ProgressCallback progress) { progress_ = std::move(progress); }
  // The camera protocol's action rule, applied to every action before sinks see it and the world
  // steps with it (head by default: actions pass unchanged).
  void SetCameraProtocol(CameraProtocol protocol) {
    protocol_ = protocol;
    proprioception_.SetCameraProtocol(protocol);
  }
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
  int64_t control_ticks() const { return control_ticks_; }

  // Collects profile() during Run: switches the env's stage timing on (and a PerEnvPolicy's
  // per-env timing) and times the driver's own parts. Call before Run. Under ood-init-pose the
  // warm-up's ticks count in both "reset" and the tick stages.
  void EnableProfile() { profiling_ = true; }
  const CellProfile& profile() const { return profile_; }

 private:
  // What a worker of the per-slot schedule has spent, added to the profile as each episode ends.
  struct SlotCosts {
    double reset = 0.0;      // the env's part of resets
    double recording = 0.0;  // wall time in sinks
    int64_t control_ticks = 0;
  };

  Observation MakeObservation() const;
  void RunLockStep();
  // Lock-step: reports the slots whose episodes have ended (stopping those a sink is done
  // with), deals the next episodes to them and to idle slots in slot order (with cameras, only on
  // ticks that are policy ticks of the batch), resets those slots in parallel, then tells the
  // policy and the sinks.
  void CollectAndRefill();
  void RunPerSlot(PerEnvPolicy& policy);
  // Per slot: `slot`'s episodes one after the other until none is left to deal.
  void RunSlot(PerEnvPolicy& policy, int slot);
  void RunSlotEpisode(PerEnvPolicy& policy, int slot, int64_t episode, SlotCosts& costs);
  // Per slot: the next episode index, or -1 when all are dealt.
  int64_t DealNext();
  // Per slot: tells the sinks and the progress callback that `slot`'s episode has ended and
  // adds its costs to the profile; one call at a time.
  void FinishSlotEpisode(int slot, SlotCosts& costs);
  // Profiling: adds each slot's cost in the parallel section just run (`slots` flags them) to
  // its episode and the section's slowest env and work to the profile; returns the env's part
  // of the work (the policy's is counted apart).
  double EndSection(const std::vector<uint8_t>& slots);
  void FinishProfile(double wall_seconds);
  template <typename Body>
  double WallSeconds(Body&& body);

  VecEnv& vec_env_;
  Policy& policy_;
  int64_t total_ = 0;         // episodes to run
  int64_t end_episode_ = 0;   // one past the last episode index
  int64_t next_episode_ = 0;  // the next episode index to deal
  int64_t finished_ = 0;
  int64_t control_ticks_ = 0;
  int64_t lock_step_ticks_ = 0;  // ticks of the lock-step loop so far
  std::vector<EpisodeSink*> sinks_;
  ProgressCallback progress_;
  CameraProtocol protocol_ = CameraProtocol::kHead;
  bool lock_step_required_ = false;
  std::mutex deal_mutex_;              // per slot: next_episode_
  std::atomic<bool> stopping_{false};  // per slot: a worker failed
  std::mutex finish_mutex_;            // per slot: episode ends, progress and the profile
  ProprioceptionBatch proprioception_;
  // Per-slot buffers, sized once.
  std::vector<const char*> prompts_;
  std::vector<uint8_t> acting_;
  std::vector<uint8_t> observed_;  // acting at a policy tick: proprioception is computed
  std::vector<uint8_t> started_;
  std::vector<EpisodeStart> starts_;
  ActionBatch actions_;
  std::vector<PolicyFault> faults_;
  bool profiling_ = false;
  CellProfile profile_;
  PerEnvPolicy* timed_policy_ = nullptr;  // the policy, when it times its envs
  double parallel_seconds_ = 0.0;         // wall time in parallel sections
  double recording_seconds_ = 0.0;        // wall time in sinks
  double policy_seconds_ = 0.0;
  double reset_seconds_ = 0.0;
  std::vector<double> episode_seconds_;  // (slots) the running episode's cost so far
  std::vector<uint8_t> all_slots_;
};

}  // namespace tavis::batch

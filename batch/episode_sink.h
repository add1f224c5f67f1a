// What is recorded while episodes run: a sink is told when an episode starts, what the policy
// chose on every control tick, when the world has moved, and when the episode ends; it may end an
// episode early once it has what it needs. Every episode loop tells its sinks the same way
// (EpisodeSlots, LockStepTicker): the episode driver's two schedules and the Python module's env.
#pragma once

#include "batch/loop_observer.h"
#include "batch/vec_env.h"
#include "kinematics/action.h"

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
  // What the observers count this sink's calls as: kSinks, or kVideo for a sink that renders and
  // encodes video (episode videos, a rollout dataset), whose time an episode's time split reports.
  virtual LoopPart timed_as() const { return LoopPart::kSinks; }
};
}  // namespace tavis::batch

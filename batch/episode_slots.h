// The env's slots as every episode loop runs them: the sinks and the observer, the camera
// protocol's action rule, each slot's prompt and the observation a policy is given; and what
// happens to one slot's episode whatever the schedule: it starts, an action is chosen for it, a
// sink is done with it, the policy gives up on it, it ends. The episode driver's per-slot
// schedule uses these pieces directly; the lock-step loop (LockStepTicker: the driver's lock-step
// schedule and the Python module's env) applies them to the whole batch.
#pragma once

#include <cstdint>
#include <vector>

#include "batch/camera_protocol.h"
#include "batch/episode_sink.h"
#include "batch/loop_observer.h"
#include "batch/policy.h"
#include "batch/proprioception.h"
#include "batch/vec_env.h"

namespace tavis::batch {

class EpisodeSlots {
 public:
  explicit EpisodeSlots(VecEnv& vec_env);

  VecEnv& vec_env() const { return vec_env_; }
  void AddSink(EpisodeSink& sink) { sinks_.push_back(&sink); }
  const std::vector<EpisodeSink*>& sinks() const { return sinks_; }
  // The camera protocol's action rule, applied to every action before sinks see it and the world
  // steps with it, and its observation.state (head by default: actions pass unchanged).
  void SetCameraProtocol(CameraProtocol protocol);
  // Null (the default): nothing observes the loop.
  void SetObserver(LoopObserver* observer) { observer_ = observer; }
  LoopObserver* observer() const { return observer_; }

  // The policy's view of the batch: state, images, prompts and proprioception as last updated.
  Observation observation() const;
  ProprioceptionBatch& proprioception() { return proprioception_; }
  const ProprioceptionBatch& proprioception() const { return proprioception_; }
  // The running or last episode's instruction in `slot`; null for a slot never started or released.
  const char* prompt(int slot) const { return prompts_[static_cast<std::size_t>(slot)]; }

  // The env of `slot` has just been reset: its episode's prompt, before the policy's reset.
  void EpisodeReset(int slot);
  // Tells every sink `tell(sink)`, each as its part of the loop for `slot` (kWholeBatch: a part
  // the batch shares; EpisodeSink::timed_as).
  template <typename Tell>
  void TellSinks(int slot, Tell&& tell) {
    for (EpisodeSink* sink : sinks_) Observe(observer_, sink->timed_as(), slot, [&] { tell(*sink); });
  }
  // Ends the running episode in `slot` as kStopped if a sink has all it needs of it; true if so.
  bool StopIfSinksAreDone(int slot);
  // The camera protocol's rule applied to an action the slot will step with.
  void ApplyProtocol(kinematics::Action& action) const { ApplyToAction(protocol_, action); }
  // The slot's action on this tick (chosen now or held), protocol applied, told to the sinks.
  void ActionChosen(int slot, kinematics::Action& action);
  // After a step: ends the running episode in `slot` as gave_up if `policy` has given up on it.
  void EndIfGaveUp(const Policy& policy, int slot);
  // Tells the observer and the sinks that the episode in `slot` has ended (state.end says how).
  // One call at a time.
  void TellEnded(int slot);
  // True once TellEnded has told of the slot's episode (until the slot is reset).
  bool told_ended(int slot) const { return told_ended_[static_cast<std::size_t>(slot)] != 0; }
  // Marks the slot idle (VecEnv::Release), with no prompt.
  void Release(int slot);

 private:
  VecEnv& vec_env_;
  std::vector<EpisodeSink*> sinks_;
  LoopObserver* observer_ = nullptr;
  CameraProtocol protocol_ = CameraProtocol::kHead;
  ProprioceptionBatch proprioception_;
  std::vector<const char*> prompts_;  // (slots)
  std::vector<uint8_t> told_ended_;   // (slots)
};

}  // namespace tavis::batch

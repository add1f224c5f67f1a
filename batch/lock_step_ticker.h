// The lock-step episode loop: every slot of the batch takes a control tick together. Its three
// steps are the same for every caller: start episodes in slots (reset, prompts, the policies'
// reset, the sinks told), one control tick with the actions given (the camera protocol's rule,
// the sinks' ActionChosen, VecEnv::Step, the episodes the policy could not act for or has given up
// on ended, the ticks counted, the sinks' Stepped), and collect the slots whose episodes have
// ended (the sinks told, once per episode). What differs is who chooses the actions and deals the
// episodes: EpisodeDriver's lock-step schedule asks its Policy and deals the cell's episodes in
// order; gym::GymVecEnv (the Python module) takes the caller's actions and resets or autoresets
// as Gymnasium's VectorEnv does. The per-slot schedule runs the same per-episode pieces
// (EpisodeSlots) slot by slot.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "batch/episode_slots.h"
#include "batch/policy.h"
#include "batch/vec_env.h"

namespace tavis::batch {

class LockStepTicker {
 public:
  // The slots (their env, sinks, observer, protocol and observation) must outlive the ticker.
  explicit LockStepTicker(EpisodeSlots& slots);

  // A policy reset (Policy::Reset) with every start, in the order added; it must outlive the ticker.
  void AddPolicy(Policy& policy) { policies_.push_back(&policy); }

  // Starts episode start.episode in slot start.env for each of `starts`: the env resets them in
  // parallel (an ood-init-pose warm-up may end an episode at once), then each slot's prompt, the
  // policies' reset of the started slots, and the sinks' EpisodeStarted in the order listed.
  void StartEpisodes(const std::vector<EpisodeStart>& starts);
  // The sinks' TickStarting: a control tick is about to begin (before the policy observes it).
  void TickStarting();
  // Renders the cameras of the envs at a policy tick (VecEnv::RenderPolicyTick).
  void RenderPolicyTick();
  // One control tick of the envs running now with `actions` (one per slot; other slots' entries
  // are ignored): an env `policy` could not act for (Policy::TakeFaults) ends invalid_action; the
  // camera protocol's rule is applied to every action, the sinks hear each running slot's, the
  // env steps; then an episode `policy` has given up on ends gave_up, and the sinks' Stepped.
  // `policy` may be null (actions from elsewhere: no faults, nobody gives up).
  void Tick(ActionBatch& actions, Policy* policy);
  // In slot order: stops the running episodes a sink is done with (kStopped), then tells of every
  // slot whose episode has ended and was not told of since it started: the observer and the
  // sinks, then `ended(slot)`. A slot stays as it is (ended) until started again or released.
  void CollectEnded(const std::function<void(int slot)>& ended);

  int RunningEnvs() const;
  // Env control ticks stepped (each running env's tick counts one).
  int64_t control_ticks() const { return control_ticks_; }

 private:
  EpisodeSlots& slots_;
  VecEnv& vec_env_;
  std::vector<Policy*> policies_;
  int64_t control_ticks_ = 0;
  // Per-slot buffers, sized once.
  std::vector<uint8_t> started_;
  std::vector<PolicyFault> faults_;
};

}  // namespace tavis::batch

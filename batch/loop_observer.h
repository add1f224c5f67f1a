// What an episode loop tells an observer about itself, so that timing stays out of the loop's
// control flow: the loop marks where its parts start and end and where episodes start and end,
// and the observer (CellProfiler, `tavis eval --profile`) measures what it wants at those points.
// A loop without an observer (a null pointer) does nothing more than run.
#pragma once

#include <cstdint>
#include <vector>

namespace tavis::batch {

class Policy;
class VecEnv;

// A part of the loop, as the observer accounts for it.
enum class LoopPart {
  kParallel,    // work spread over the threads: a batch call of the env, a policy's reset, the per-slot workers
  kPolicyActs,  // the policy choosing the batch's actions (spread over the threads too)
  kSinks,       // the sinks being told something
};

// The slot a part belongs to when the whole batch shares it (the lock-step schedule's parts).
constexpr int kWholeBatch = -1;

// Every hook does nothing by default. Hooks for distinct slots (slot >= 0) may come concurrently
// from the per-slot schedule's workers; EpisodeEnding and EpisodeEnded come one end at a time.
class LoopObserver {
 public:
  virtual ~LoopObserver() = default;
  // EpisodeDriver::Run is starting on `vec_env` with `policy`, on the per-slot schedule or
  // lock-step; and has ended (not called when the run throws).
  virtual void RunStarting(VecEnv& /*vec_env*/, Policy& /*policy*/, bool /*per_slot*/) {}
  virtual void RunEnded() {}
  // A part of the loop for `slot` (kWholeBatch: the batch's) is starting, and has ended.
  virtual void PartStarting(LoopPart /*part*/, int /*slot*/) {}
  virtual void PartEnded(LoopPart /*part*/, int /*slot*/) {}
  // Lock-step: the flagged slots have been reset together and the policy reset for them (before
  // the sinks hear of it); a control tick of the batch has been stepped (before the sinks' Stepped).
  virtual void EpisodesStarted(const std::vector<uint8_t>& /*started*/) {}
  virtual void TickEnded() {}
  // Per slot: `slot`'s env has been reset on its own, before the policy's reset.
  virtual void EnvReset(int /*slot*/) {}
  // The episode in `slot` has ended: before the sinks are told, and after.
  virtual void EpisodeEnding(int /*slot*/) {}
  virtual void EpisodeEnded(int /*slot*/) {}
};

// Runs `body` as `part` of the loop for `slot`, telling `observer` (if any) before and after.
template <typename Body>
void Observe(LoopObserver* observer, LoopPart part, int slot, Body&& body) {
  if (observer != nullptr) observer->PartStarting(part, slot);
  body();
  if (observer != nullptr) observer->PartEnded(part, slot);
}

}  // namespace tavis::batch

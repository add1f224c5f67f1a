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

// A part of the loop, as the observers account for it: the profiler by where the threads work
// (every part of the batch but the sinks runs spread over them), the episode timer by what it is
// (cell/episode_timer.h: policy, physics, rendering, video, the rest).
enum class LoopPart {
  kParallel,      // other work spread over the threads: the per-slot workers
  kReset,         // envs being reset (an ood-init-pose warm-up included)
  kPolicyResets,  // the policy reset for the episodes just started
  kRender,        // the policy's cameras rendered
  kPolicyActs,    // the policy choosing actions
  kStep,          // the env's control tick: IK, the physics substeps, the neck, the task, the ends
  kSinks,         // a sink being told something
  kVideo,         // a sink that renders and encodes video being told something (EpisodeSink::timed_as)
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
  // Lock-step: the flagged slots are about to be reset together (before the env's reset), and
  // have been reset and the policy reset for them (before the sinks hear of it); a control tick
  // of the batch has been stepped (before the sinks' Stepped).
  virtual void EpisodesStarting(const std::vector<uint8_t>& /*starting*/) {}
  virtual void EpisodesStarted(const std::vector<uint8_t>& /*started*/) {}
  virtual void TickEnded() {}
  // Per slot: `slot`'s env has been reset on its own (the part kReset of the slot just ended),
  // before the policy's reset.
  virtual void EnvReset(int /*slot*/) {}
  // The episode in `slot` has ended: before the sinks are told, and after.
  virtual void EpisodeEnding(int /*slot*/) {}
  virtual void EpisodeEnded(int /*slot*/) {}
};

// Several observers of one loop, told in the order added (a cell's episode timer and its
// profiler); each must outlive the loop's run.
class LoopObservers : public LoopObserver {
 public:
  void Add(LoopObserver& observer) { observers_.push_back(&observer); }

  void RunStarting(VecEnv& vec_env, Policy& policy, bool per_slot) override {
    for (LoopObserver* observer : observers_) observer->RunStarting(vec_env, policy, per_slot);
  }
  void RunEnded() override {
    for (LoopObserver* observer : observers_) observer->RunEnded();
  }
  void PartStarting(LoopPart part, int slot) override {
    for (LoopObserver* observer : observers_) observer->PartStarting(part, slot);
  }
  void PartEnded(LoopPart part, int slot) override {
    for (LoopObserver* observer : observers_) observer->PartEnded(part, slot);
  }
  void EpisodesStarting(const std::vector<uint8_t>& starting) override {
    for (LoopObserver* observer : observers_) observer->EpisodesStarting(starting);
  }
  void EpisodesStarted(const std::vector<uint8_t>& started) override {
    for (LoopObserver* observer : observers_) observer->EpisodesStarted(started);
  }
  void TickEnded() override {
    for (LoopObserver* observer : observers_) observer->TickEnded();
  }
  void EnvReset(int slot) override {
    for (LoopObserver* observer : observers_) observer->EnvReset(slot);
  }
  void EpisodeEnding(int slot) override {
    for (LoopObserver* observer : observers_) observer->EpisodeEnding(slot);
  }
  void EpisodeEnded(int slot) override {
    for (LoopObserver* observer : observers_) observer->EpisodeEnded(slot);
  }

 private:
  std::vector<LoopObserver*> observers_;
};

// Runs `body` as `part` of the loop for `slot`, telling `observer` (if any) before and after.
template <typename Body>
void Observe(LoopObserver* observer, LoopPart part, int slot, Body&& body) {
  if (observer != nullptr) observer->PartStarting(part, slot);
  body();
  if (observer != nullptr) observer->PartEnded(part, slot);
}

}  // namespace tavis::batch

// Every episode's time split (episode_times.h), measured from outside the episode loop as the
// profiler is: a LoopObserver that reads the clock where the loop's parts start and end (a few
// reads per tick) and adds each interval to the part it was in. An evaluation cell always plugs
// one in; the records never see it.
//
// How an interval is attributed (docs/performance.md, "Where an episode's time goes"):
//   per slot: each worker runs one episode at a time on its own thread, so every interval of the
//     slot's parts is that episode's alone; its parts add up to its span.
//   lock-step: every part is a call for the whole batch, which every live episode waits for, so
//     each interval is shared equally among the episodes live during it (started, not yet told
//     ended); a part's total over the episodes is then the loop's time in it, and an episode's
//     parts add up to less than its span.
// The parts: policy (its actions and its reset for the episodes started), physics (the env's
// control tick), render (the policy's cameras), video (the sinks that film: episode videos, a
// rollout dataset), other (the env's reset, the records' sink, the loop itself).
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <vector>

#include "batch/cell/episode_times.h"
#include "batch/loop_observer.h"

namespace tavis::batch::cell {

class EpisodeTimer : public LoopObserver {
 public:
  // The times of `episode` once it has ended (EpisodeEnding), taken once; none if it never ran
  // under this timer.
  std::optional<EpisodeTimes> Take(int64_t episode);

  void RunStarting(VecEnv& vec_env, Policy& policy, bool per_slot) override;
  void PartStarting(LoopPart part, int slot) override;
  void PartEnded(LoopPart part, int slot) override;
  void EpisodesStarting(const std::vector<uint8_t>& starting) override;
  void EpisodeEnding(int slot) override;

 private:
  using Clock = std::chrono::steady_clock;
  using Seconds = std::array<double, EpisodeTimes::kNumParts>;

  // One slot's running episode: per slot, its own clock; lock-step, where the batch's shares
  // stood when it started. A cache line each: per slot, each worker writes its own.
  struct alignas(64) Lane {
    Clock::time_point start;
    Clock::time_point last;                          // per slot: the last interval's end
    EpisodeTimes::Part part = EpisodeTimes::kOther;  // per slot: the part running since `last`
    Seconds seconds{};                               // per slot: the episode's so far; lock-step: shares_ at its start
  };

  // Per slot: the slot's interval since its last event goes to its part, which is now `next`.
  void AdvanceLane(Lane& lane, Clock::time_point now, EpisodeTimes::Part next);
  // Lock-step: the interval since the last event is shared among the live episodes (none live:
  // it goes to none), and the batch's part is now `next`.
  void AdvanceBatch(Clock::time_point now, EpisodeTimes::Part next);

  const VecEnv* vec_env_ = nullptr;
  bool per_slot_ = false;
  std::vector<Lane> lanes_;  // [slot]
  // Lock-step: the part the batch is in since `batch_last_`, the live episodes, and what one
  // episode live since the run started would have had of each part (its share of every interval).
  Clock::time_point batch_last_;
  EpisodeTimes::Part batch_part_ = EpisodeTimes::kOther;
  int live_ = 0;
  Seconds shares_{};
  std::mutex ended_mutex_;                 // per slot, ends and takes may come from any worker
  std::map<int64_t, EpisodeTimes> ended_;  // by episode, until taken
};

}  // namespace tavis::batch::cell

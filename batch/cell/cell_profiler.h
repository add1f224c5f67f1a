// Where a cell's time goes, measured from outside the episode loop: the loop tells this observer
// where its parts (parallel work, the policy, the sinks) and its episodes start and end, and the
// profiler times them, switches the env's stage timing and a PerEnvPolicy's per-env timing on,
// and at the end of the run puts them together into a CellProfile (batch/cell/cell_profile.h).
// An evaluation cell with `profile` set plugs one into its EpisodeDriver (SetObserver); `tavis eval
// --profile` prints and writes its profile.
#pragma once

#include <chrono>
#include <cstdint>
#include <vector>

#include "batch/cell/cell_profile.h"
#include "batch/loop_observer.h"

namespace tavis::batch {
class PerEnvPolicy;
}  // namespace tavis::batch

namespace tavis::batch::cell {

class CellProfiler : public LoopObserver {
 public:
  // The profile of the last run, complete once RunEnded has been called.
  const CellProfile& profile() const { return profile_; }

  // Under ood-init-pose the warm-up's ticks count in both "reset" and the tick stages.
  void RunStarting(VecEnv& vec_env, Policy& policy, bool per_slot) override;
  void RunEnded() override;
  void PartStarting(LoopPart part, int slot) override;
  void PartEnded(LoopPart part, int slot) override;
  void EpisodesStarted(const std::vector<uint8_t>& started) override;
  void TickEnded() override;
  void EnvReset(int slot) override;
  void EpisodeEnding(int slot) override;
  void EpisodeEnded(int slot) override;

 private:
  using Clock = std::chrono::steady_clock;
  static double SecondsSince(Clock::time_point start);
  // Lock-step: adds each flagged slot's cost in the parallel section just run (`slots` flags
  // them) to its episode, and the section's slowest env and work to the profile; returns the
  // env's part of the work (the policy's is counted apart).
  double EndSection(const std::vector<uint8_t>& slots);

  VecEnv* vec_env_ = nullptr;
  PerEnvPolicy* timed_policy_ = nullptr;  // the policy, when it times its envs
  CellProfile profile_;
  Clock::time_point run_start_;
  std::vector<Clock::time_point> part_start_;  // (slots + 1) [slot + 1]: the part running for it
  Clock::time_point end_start_;                // the episode end being told (one at a time)
  double parallel_seconds_ = 0.0;              // wall time in parallel sections
  double recording_seconds_ = 0.0;             // wall time in sinks
  double policy_seconds_ = 0.0;
  double reset_seconds_ = 0.0;
  std::vector<double> episode_seconds_;  // (slots) lock-step: the running episode's cost so far
  std::vector<uint8_t> all_slots_;
  // (slots) per slot: the running episode's reset cost and time in sinks so far
  std::vector<double> slot_reset_seconds_;
  std::vector<double> slot_recording_seconds_;
};

}  // namespace tavis::batch::cell

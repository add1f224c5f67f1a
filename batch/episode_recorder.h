// The sink of an evaluation cell: per episode its outcome, length, solver messages and the
// commanded action of every control tick (for GALT), in episode order.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "batch/episode_driver.h"
#include "engine/batch_state.h"
#include "kinematics/action.h"
#include "kinematics/galt.h"

namespace tavis::batch {

struct EpisodeRecord {
  int64_t episode = 0;
  bool success = false;
  engine::EpisodeEnd end = engine::EpisodeEnd::kRunning;
  int length_steps = 0;          // policy-rate (20 Hz) steps, as the reference counts them
  int length_control_ticks = 0;  // 60 Hz control ticks
  int solver_messages = 0;       // ODE solver messages (degenerate contacts), for diagnosis
  engine::InvalidAction invalid_action;  // what ended it, when end is kInvalidAction
  std::vector<kinematics::Action> actions;  // commanded action of every control tick
  // GALT of the commanded actions at the policy's action rate, for successful episodes only
  // (the reference computes it for those).
  std::optional<kinematics::GaltResult> galt;
  // The same at the 20 Hz policy rate, for a policy acting faster (the scripted experts at 60 Hz),
  // as the paper's validation table reports both.
  std::optional<kinematics::GaltResult> galt_policy_rate;
};

class EpisodeRecorder : public EpisodeSink {
 public:
  // Records episodes 0..episodes-1 run on `slots` env slots.
  EpisodeRecorder(int64_t episodes, int slots, int max_control_steps);

  void EpisodeStarted(const VecEnv& env, int slot) override;
  void ActionsChosen(const VecEnv& env, const ActionBatch& actions) override;
  void EpisodeEnded(const VecEnv& env, int slot) override;

  std::vector<EpisodeRecord>& records() { return records_; }  // by episode index
  int successes() const { return successes_; }

 private:
  std::vector<EpisodeRecord> records_;
  std::vector<std::vector<kinematics::Action>> action_logs_;  // [slot], reserved for a whole episode
  int successes_ = 0;
};

}  // namespace tavis::batch

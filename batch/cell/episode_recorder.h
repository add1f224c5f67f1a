// The sink of an evaluation cell: per episode its outcome, length, solver messages and GALT,
// computed when the episode ends from the commanded actions of its control ticks, which are then
// dropped (unless asked to keep them), so a cell's memory does not grow with its episodes.
// Records are handed on in episode order, whatever order the slots finish in.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "batch/cell/episode_times.h"
#include "batch/cell/failure_events.h"
#include "batch/cell/gaze_fixation.h"
#include "batch/cell/motion_quality.h"
#include "batch/episode_driver.h"
#include "engine/batch_state.h"
#include "kinematics/action.h"
#include "kinematics/galt.h"
#include "scenarios/stage_progress.h"

namespace tavis::batch::cell {

// One of the task's stages (scenarios/stage.h) in an episode: the control tick it was first
// reached at, -1 if never.
struct StageReached {
  std::string name;
  int first_tick = -1;

  bool reached() const { return first_tick >= 0; }
  bool operator==(const StageReached& other) const { return name == other.name && first_tick == other.first_tick; }
};

struct EpisodeRecord {
  int64_t episode = 0;
  bool success = false;
  engine::EpisodeEnd end = engine::EpisodeEnd::kRunning;
  int length_steps = 0;                  // policy-rate (20 Hz) steps, as the reference counts them
  int length_control_ticks = 0;          // 60 Hz control ticks
  int solver_messages = 0;               // ODE solver messages (degenerate contacts), for diagnosis
  engine::InvalidAction invalid_action;  // what ended it, when end is kInvalidAction
  // GALT of the commanded actions at the policy's action rate, for successful episodes only
  // (the reference computes it for those).
  std::optional<kinematics::GaltResult> galt;
  // The same at the 20 Hz policy rate, for a policy acting faster (the scripted experts at 60 Hz),
  // as the paper's validation table reports both.
  std::optional<kinematics::GaltResult> galt_policy_rate;
  // What the episode was about: the instruction the policy received, the target object's model
  // name and the task's facts about it (its side, shelf, the box's open side).
  std::string prompt;
  std::string target_object;
  scenarios::TargetFacts target;
  // Under a runtime perturbation level only: the control tick the target was moved, -1 if it was
  // not (no hand came near it, or no free place was found); unset in every other cell.
  std::optional<int> target_move_tick;
  std::vector<StageReached> stages;  // the task's stages, in declared order
  // What went wrong (failure_events.h: the events that fired, in declared order, each with its
  // first control tick) and how each arm moved (motion_quality.h, by kinematics::Index); unset in
  // a record written before they existed.
  std::optional<std::vector<EventFired>> events;
  std::optional<std::array<ArmMotion, 2>> motion;
  GazeRecord gaze;  // where the head looked (gaze_fixation.h); untraced for a robot without a head
  std::vector<kinematics::Action> replay_actions;  // one every RecordSettings::replay_stride ticks
  std::vector<kinematics::Action> actions;         // every control tick's, with RecordSettings::keep_actions
  // How long it took and where the time went (episode_times.h), set by the cell that ran it (none
  // for a resumed episode whose times were lost). Not part of the record: it differs from run to
  // run, so episodes.jsonl never holds it and no comparison of records reads it.
  std::optional<EpisodeTimes> times;
};

struct RecordSettings {
  // GALT sampled every galt_stride control ticks at galt_fps (the policy's action rate); 0: no
  // GALT (the fixed protocol has no head to lead).
  int galt_stride = 0;
  double galt_fps = 0.0;
  // Also at the policy rate, for a policy acting faster; 0: not.
  int policy_rate_stride = 0;
  double policy_rate_fps = 0.0;
  int replay_stride = 0;      // keep the actions a served policy chose, for --policy replay; 0: none
  bool keep_actions = false;  // keep every control tick's action in the record (tests compare them)
  // Hand records on in episode order (the driver deals episodes in sequence); false: as each
  // episode ends (the Python module, whose caller may deal episodes in any order).
  bool in_episode_order = true;
  // The head moves (not a fixed view, which zeroes the neck): the gaze events apply.
  bool head_moves = true;
};

class EpisodeRecorder : public EpisodeSink {
 public:
  using Finished = std::function<void(EpisodeRecord&&)>;

  // Records the episodes from `first_episode` on, run on `slots` env slots, handing each to
  // `finished` in episode order.
  EpisodeRecorder(int slots, int max_control_steps, RecordSettings settings, int64_t first_episode, Finished finished);

  void EpisodeStarted(const VecEnv& vec_env, int slot) override;
  void ActionChosen(const VecEnv& vec_env, int slot, const kinematics::Action& action) override;
  void EpisodeEnded(const VecEnv& vec_env, int slot) override;
  // Per-slot logs, and records put in episode order whatever order episodes end in.
  bool works_per_slot() const override { return true; }

 private:
  // The slot's state at a tick shown to the stages: its events and its hands' path.
  void ObserveMotion(const VecEnv& vec_env, int slot);
  std::optional<kinematics::GaltResult> Galt(const std::vector<kinematics::Action>& log, int stride, double fps) const;

  RecordSettings settings_;
  Finished finished_;
  std::vector<std::vector<kinematics::Action>> action_logs_;  // [slot], reserved for a whole episode
  // [slot]: made at the slot's first episode (the recorder learns the task from the env then);
  // each slot touches only its own.
  std::vector<std::optional<scenarios::StageProgress>> stage_progress_;
  std::vector<std::optional<FailureEventDetector>> event_detectors_;  // [slot], made with its StageProgress
  // [slot][hand]: the tool centre point at every tick shown, reserved for a whole episode.
  std::vector<std::array<std::vector<Vec3>, 2>> tcp_logs_;
  std::vector<std::optional<GazeTracer>> gaze_tracers_;  // [slot], made with its StageProgress
  std::vector<GazeRecord> gaze_;                         // [slot] the running episode's fixations
  std::vector<std::string> prompts_;                     // [slot] the running episode's prompt
  std::vector<std::string> target_objects_;              // [slot]
  std::vector<scenarios::TargetFacts> targets_;          // [slot]
  int64_t next_release_;
  std::map<int64_t, EpisodeRecord> waiting_;  // ended, after an episode still running
};

}  // namespace tavis::batch::cell

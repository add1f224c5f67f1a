#include "batch/cell/episode_recorder.h"

#include "batch/cell/gaze_anchors.h"
#include "batch/vec_env.h"

namespace tavis::batch::cell {

EpisodeRecorder::EpisodeRecorder(int slots, int max_control_steps, RecordSettings settings, int64_t first_episode,
                                 Finished finished)
    : settings_(settings),
      finished_(std::move(finished)),
      action_logs_(static_cast<std::size_t>(slots)),
      stage_progress_(static_cast<std::size_t>(slots)),
      event_detectors_(static_cast<std::size_t>(slots)),
      tcp_logs_(static_cast<std::size_t>(slots)),
      gaze_tracers_(static_cast<std::size_t>(slots)),
      gaze_(static_cast<std::size_t>(slots)),
      prompts_(static_cast<std::size_t>(slots)),
      target_objects_(static_cast<std::size_t>(slots)),
      targets_(static_cast<std::size_t>(slots)),
      next_release_(first_episode) {
  for (auto& log : action_logs_) log.reserve(static_cast<std::size_t>(max_control_steps));
  for (auto& hands : tcp_logs_) {
    for (auto& log : hands) log.reserve(static_cast<std::size_t>(max_control_steps) + 1);
  }
}

void EpisodeRecorder::EpisodeStarted(const VecEnv& vec_env, int slot) {
  action_logs_[slot].clear();
  const scenarios::ScenarioDef& scenario = vec_env.scenario();
  const engine::BatchState& state = vec_env.state();
  std::optional<scenarios::StageProgress>& progress = stage_progress_[slot];
  if (!progress) progress.emplace(scenario, vec_env.model());
  progress->Start();
  std::optional<FailureEventDetector>& detector = event_detectors_[slot];
  if (!detector) detector.emplace(scenario, vec_env.model(), settings_.head_moves);
  detector->Start();
  for (auto& log : tcp_logs_[slot]) log.clear();
  if (!gaze_tracers_[slot]) gaze_tracers_[slot].emplace(vec_env.model(), scenario.cue_objects);
  gaze_[slot] = GazeRecord{};
  gaze_[slot].traced = gaze_tracers_[slot]->has_head();
  prompts_[slot] = vec_env.prompt(slot);
  target_objects_[slot] = vec_env.model().objects[static_cast<std::size_t>(state.target(slot))].name;
  targets_[slot] = scenario.target_facts != nullptr ? scenario.target_facts(state, slot) : scenarios::TargetFacts{};
}

void EpisodeRecorder::ActionChosen(const VecEnv& vec_env, int slot, const kinematics::Action& action) {
  // The gaze at each policy tick of the log (GALT's clock), in the state the action is chosen in.
  const int ticks_per_policy_step = vec_env.model().physics.controls_per_policy();
  const int tick = static_cast<int>(action_logs_[slot].size());
  if (gaze_[slot].traced && tick % ticks_per_policy_step == 0) {
    AppendFixation(gaze_tracers_[slot]->Trace(vec_env.state(), slot, action), tick / ticks_per_policy_step,
                   gaze_[slot].fixations);
  }
  action_logs_[slot].push_back(action);
  // The state this tick's action is chosen in: every state of the episode but its last, which
  // EpisodeEnded looks at.
  stage_progress_[slot]->Observe(vec_env.state(), slot);
  ObserveMotion(vec_env, slot);
}

void EpisodeRecorder::ObserveMotion(const VecEnv& vec_env, int slot) {
  const HandFrames hands = ComputeHandFrames(vec_env.model().robot, vec_env.state().q_row(slot));
  event_detectors_[slot]->Observe(vec_env.state(), slot, hands, stage_progress_[slot]->first_ticks());
  for (std::size_t hand = 0; hand < 2; ++hand) tcp_logs_[slot][hand].push_back(hands.tcp[hand]);
}

std::optional<kinematics::GaltResult> EpisodeRecorder::Galt(const std::vector<kinematics::Action>& log, int stride,
                                                            double fps) const {
  if (stride <= 0 || log.empty()) return std::nullopt;
  const kinematics::TrajectoryView every_tick{log.front().data(), static_cast<int>(log.size()),
                                              kinematics::action::kSize};
  return kinematics::ComputeGalt(every_tick.Downsampled(stride), fps);
}

void EpisodeRecorder::EpisodeEnded(const VecEnv& vec_env, int slot) {
  const engine::BatchState& state = vec_env.state();
  const int ticks_per_policy_step = vec_env.model().physics.controls_per_policy();
  const std::vector<kinematics::Action>& log = action_logs_[slot];
  EpisodeRecord record;
  record.episode = state.episode[slot];
  record.end = state.end[slot];
  record.success = state.end[slot] == engine::EpisodeEnd::kSuccess;
  record.length_control_ticks = state.control_step[slot];
  record.length_steps = (state.control_step[slot] + ticks_per_policy_step - 1) / ticks_per_policy_step;
  record.solver_messages = vec_env.solver_messages(slot);
  record.invalid_action = state.invalid_action[slot];
  record.prompt = prompts_[slot];
  record.target_object = target_objects_[slot];
  record.target = targets_[slot];
  if (vec_env.model().episode_perturbation.moves_target()) record.target_move_tick = state.task[slot].target_move_tick;
  scenarios::StageProgress& progress = *stage_progress_[slot];
  progress.Observe(state, slot);
  const std::vector<scenarios::StageDef>& stages = vec_env.scenario().stages;
  for (std::size_t i = 0; i < stages.size(); ++i) record.stages.push_back({stages[i].name, progress.first_ticks()[i]});
  ObserveMotion(vec_env, slot);
  const std::array<std::vector<Vec3>, 2>& tcp_log = tcp_logs_[slot];
  record.events = event_detectors_[slot]->Finish(state, slot, progress.first_ticks(), tcp_log);
  const double control_hz = vec_env.model().physics.control_hz;
  record.motion =
      std::array<ArmMotion, 2>{MeasureArmMotion(tcp_log[0], control_hz), MeasureArmMotion(tcp_log[1], control_hz)};
  if (record.success) {
    record.galt = Galt(log, settings_.galt_stride, settings_.galt_fps);
    record.galt_policy_rate = Galt(log, settings_.policy_rate_stride, settings_.policy_rate_fps);
  }
  record.gaze = std::move(gaze_[slot]);
  if (record.success) {
    VerifyGalt(record.galt, vec_env.model().physics.policy_hz, !vec_env.scenario().cue_objects.empty(), record.gaze);
  }
  if (record.gaze.traced) {
    // Successful episodes only, as GALT: a failed one's anchors are all unset.
    AnchorEvents events;
    if (record.success) {
      events = {record.galt ? &*record.galt : nullptr, &stages, &progress.first_ticks(), control_hz};
    }
    record.gaze.anchors = MeasureGazeAnchors(vec_env.scenario().gaze_anchors, record.gaze.fixations, events,
                                             vec_env.model().physics.policy_hz);
  }
  if (settings_.replay_stride > 0) {
    for (std::size_t tick = 0; tick < log.size(); tick += static_cast<std::size_t>(settings_.replay_stride)) {
      record.replay_actions.push_back(log[tick]);
    }
  }
  if (settings_.keep_actions) record.actions = log;
  if (!settings_.in_episode_order) {
    finished_(std::move(record));
    return;
  }
  waiting_[record.episode] = std::move(record);
  for (auto next = waiting_.find(next_release_); next != waiting_.end(); next = waiting_.find(next_release_)) {
    finished_(std::move(next->second));
    waiting_.erase(next);
    ++next_release_;
  }
}

}  // namespace tavis::batch::cell

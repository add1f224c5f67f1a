#include "batch/rollout/rollout_recorder.h"

#include <cmath>

#include <tbb/parallel_for.h>

#include "batch/dataset/frame_capture.h"

namespace tavis::batch::rollout {
namespace {

bool Finite(const kinematics::Action& action) {
  for (double value : action) {
    if (!std::isfinite(value)) return false;
  }
  return true;
}

}  // namespace

struct RolloutRecorder::Slot {
  bool recording = false;
  dataset::RecordedEpisode episode;
  std::vector<dataset::video::EpisodeEncoder> encoders;  // per camera, for the running episode
  kinematics::Action action{};                           // this tick's
};

RolloutRecorder::RolloutRecorder(const VecEnv& vec_env, CameraProtocol protocol, std::vector<std::string> cameras,
                                 dataset::video::VideoSettings video, Keep keep)
    : cameras_(std::move(cameras)),
      video_(video),
      keep_(std::move(keep)),
      ticks_per_frame_(vec_env.model().physics.controls_per_policy()),
      proprioception_(vec_env.model().robot, vec_env.num_envs()),
      slots_(static_cast<std::size_t>(vec_env.num_envs())),
      observed_(static_cast<std::size_t>(vec_env.num_envs()), 0),
      acted_(static_cast<std::size_t>(vec_env.num_envs()), 0) {
  proprioception_.SetCameraProtocol(protocol);
  if (cameras_.empty()) return;
  CameraSettings settings;
  settings.cameras = cameras_;
  settings.width = video_.width;
  settings.height = video_.height;
  render_ = std::make_unique<SceneRender>(vec_env.model(), vec_env.num_envs(), settings);
  // The task's black cameras are black here too, as the policy receives them.
  for (const std::string& name : vec_env.scenario().black_cameras) {
    const int camera = render_->CameraIndex(name);
    if (camera < 0) continue;
    for (int slot = 0; slot < vec_env.num_envs(); ++slot) render_->SetCameraEnabled(slot, camera, false);
  }
}

RolloutRecorder::~RolloutRecorder() = default;

void RolloutRecorder::EpisodeStarted(const VecEnv& vec_env, int slot) {
  Slot& recording = slots_[static_cast<std::size_t>(slot)];
  recording.recording = true;
  recording.episode = dataset::RecordedEpisode();
  recording.episode.source_episode = vec_env.state().episode[slot];
  recording.episode.prompt = vec_env.prompt(slot);
  recording.episode.image_stats.assign(cameras_.size(), dataset::ImageStats());
  recording.encoders.clear();
  for (const std::string& camera : cameras_) recording.encoders.emplace_back(video_, camera);
}

bool RolloutRecorder::Observes(const engine::BatchState& state, int slot) {
  const bool take = slots_[static_cast<std::size_t>(slot)].recording && state.running(slot) &&
                    state.control_step[slot] % ticks_per_frame_ == 0;
  observed_[static_cast<std::size_t>(slot)] = take ? 1 : 0;
  acted_[static_cast<std::size_t>(slot)] = 0;
  return take;
}

void RolloutRecorder::TickStarting(const VecEnv& vec_env) {
  const engine::BatchState& state = vec_env.state();
  bool any = false;
  for (int slot = 0; slot < state.num_envs; ++slot) any = Observes(state, slot) || any;
  if (!any) return;
  // Kept in the buffers until Stepped, when the frame's action is known to have been stepped.
  proprioception_.Update(state, observed_);
  if (render_) render_->Render(state, observed_.data());
}

void RolloutRecorder::SlotTickStarting(const VecEnv& vec_env, int slot) {
  const engine::BatchState& state = vec_env.state();
  if (!Observes(state, slot)) return;
  proprioception_.UpdateEnv(state, slot);
  if (render_) render_->RenderEnv(state, slot);
}

void RolloutRecorder::ActionChosen(const VecEnv&, int slot, const kinematics::Action& action) {
  if (!observed_[static_cast<std::size_t>(slot)] || !Finite(action)) return;  // a non-finite action is not stepped
  acted_[static_cast<std::size_t>(slot)] = 1;
  slots_[static_cast<std::size_t>(slot)].action = action;
}

void RolloutRecorder::AppendState(int slot) {
  Slot& recording = slots_[static_cast<std::size_t>(slot)];
  dataset::AppendFrameState(proprioception_, slot, recording.action, &recording.episode);
}

void RolloutRecorder::AppendImage(int slot, int camera) {
  Slot& recording = slots_[static_cast<std::size_t>(slot)];
  dataset::AppendFrameImage(render_->images(), slot, camera, &recording.encoders[static_cast<std::size_t>(camera)],
                            &recording.episode.image_stats[static_cast<std::size_t>(camera)]);
}

void RolloutRecorder::Stepped(const VecEnv& vec_env) {
  const int slots = vec_env.num_envs();
  const int cameras = static_cast<int>(cameras_.size());
  // Every (slot, camera) stream is its own encoder: the frames are taken in parallel.
  tbb::parallel_for(0, slots * std::max(cameras, 1), [&](int item) {
    const int slot = item / std::max(cameras, 1);
    const int camera = item % std::max(cameras, 1);
    if (!acted_[static_cast<std::size_t>(slot)]) return;
    if (camera == 0) AppendState(slot);
    if (camera < cameras) AppendImage(slot, camera);
  });
  std::fill(acted_.begin(), acted_.end(), 0);
}

void RolloutRecorder::SlotStepped(const VecEnv&, int slot) {
  if (!acted_[static_cast<std::size_t>(slot)]) return;
  AppendState(slot);
  for (int camera = 0; camera < static_cast<int>(cameras_.size()); ++camera) AppendImage(slot, camera);
  acted_[static_cast<std::size_t>(slot)] = 0;
}

void RolloutRecorder::EpisodeEnded(const VecEnv&, int slot) {
  Slot& recording = slots_[static_cast<std::size_t>(slot)];
  if (!recording.recording) return;
  for (dataset::video::EpisodeEncoder& encoder : recording.encoders)
    recording.episode.videos.push_back(encoder.Finish());
  recording.encoders.clear();
  recording.recording = false;
  ended_[recording.episode.source_episode] = std::move(recording.episode);
}

void RolloutRecorder::RecordFinished(const cell::EpisodeRecord& record) {
  const auto found = ended_.find(record.episode);
  if (found == ended_.end()) return;
  dataset::RecordedEpisode episode = std::move(found->second);
  ended_.erase(found);
  keep_(std::move(episode), record);
}

}  // namespace tavis::batch::rollout

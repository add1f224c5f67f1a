#include "batch/dataset/demo_recorder.h"

#include <algorithm>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "batch/dataset/frame_capture.h"
#include "kinematics/action.h"

namespace tavis::batch::dataset {
namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

}  // namespace

struct DemoRecorder::Slot {
  RecordedEpisode episode;
  std::vector<video::EpisodeEncoder> encoders;  // per camera, for the running episode
  kinematics::Action action{};                  // this tick's
  RecordingTimes times;                         // per-slot schedule: added to times_ when the episode ends
};

DemoRecorder::DemoRecorder(const batch::VecEnv& vec_env, DemoRecording recording, int64_t first_episode, Keep keep)
    : recording_(std::move(recording)),
      keep_(std::move(keep)),
      proprioception_(vec_env.model().robot, vec_env.num_envs()),
      slots_(static_cast<std::size_t>(vec_env.num_envs())),
      acted_(static_cast<std::size_t>(vec_env.num_envs()), 0),
      recorded_(static_cast<std::size_t>(vec_env.num_envs()), 0),
      next_release_(first_episode) {
  if (recording_.stride < 1) throw std::invalid_argument("the recording stride must be at least 1");
  if (recording_.cameras.empty()) return;
  batch::CameraSettings cameras;
  cameras.cameras = recording_.cameras;
  cameras.width = recording_.video.width;
  cameras.height = recording_.video.height;
  render_ = std::make_unique<batch::SceneRender>(vec_env.model(), vec_env.num_envs(), cameras);
  // The task's black cameras are black in the dataset, as the reference records them.
  for (const std::string& name : vec_env.scenario().black_cameras) {
    const int camera = render_->CameraIndex(name);
    if (camera < 0) continue;
    for (int slot = 0; slot < vec_env.num_envs(); ++slot) render_->SetCameraEnabled(slot, camera, false);
  }
}

DemoRecorder::~DemoRecorder() = default;

void DemoRecorder::EpisodeStarted(const batch::VecEnv& vec_env, int slot) {
  Slot& recording = slots_[static_cast<std::size_t>(slot)];
  recording.episode = RecordedEpisode();
  recording.episode.source_episode = vec_env.state().episode[slot];
  recording.episode.task_index = recording_.task_index;
  recording.episode.prompt = vec_env.prompt(slot);
  recording.episode.image_stats.assign(recording_.cameras.size(), ImageStats());
  recording.encoders.clear();
  for (const std::string& camera : recording_.cameras) recording.encoders.emplace_back(recording_.video, camera);
}

void DemoRecorder::ActionChosen(const batch::VecEnv&, int slot, const kinematics::Action& action) {
  acted_[static_cast<std::size_t>(slot)] = 1;
  slots_[static_cast<std::size_t>(slot)].action = action;
}

bool DemoRecorder::TakesFrame(const engine::BatchState& state, int slot) {
  // control_step is now t + 1 for the tick t just stepped; the tick that ended the episode is not recorded.
  const bool take = acted_[static_cast<std::size_t>(slot)] && state.running(slot) &&
                    (state.control_step[slot] - 1) % recording_.stride == 0;
  acted_[static_cast<std::size_t>(slot)] = 0;  // set again by the next tick's ActionChosen
  return take;
}

void DemoRecorder::CaptureState(int slot) {
  Slot& recording = slots_[static_cast<std::size_t>(slot)];
  AppendFrameState(proprioception_, slot, recording.action, &recording.episode);
}

void DemoRecorder::EncodeImage(int slot, int camera) {
  Slot& recording = slots_[static_cast<std::size_t>(slot)];
  AppendFrameImage(render_->images(), slot, camera, &recording.encoders[static_cast<std::size_t>(camera)],
                   &recording.episode.image_stats[static_cast<std::size_t>(camera)]);
}

void DemoRecorder::Stepped(const batch::VecEnv& vec_env) {
  const engine::BatchState& state = vec_env.state();
  bool any = false;
  for (int slot = 0; slot < state.num_envs; ++slot) {
    recorded_[static_cast<std::size_t>(slot)] = TakesFrame(state, slot) ? 1 : 0;
    any = any || recorded_[static_cast<std::size_t>(slot)] != 0;
  }
  if (!any) return;

  Clock::time_point start = Clock::now();
  proprioception_.Update(state, recorded_);
  for (int slot = 0; slot < state.num_envs; ++slot) {
    if (recorded_[static_cast<std::size_t>(slot)]) CaptureState(slot);
  }
  times_.capture_s += SecondsSince(start);
  if (!render_) return;

  start = Clock::now();
  render_->Render(state, recorded_.data());
  times_.render_s += SecondsSince(start);

  // Every (slot, camera) stream is its own encoder: encode them in parallel.
  start = Clock::now();
  const int cameras = static_cast<int>(recording_.cameras.size());
  tbb::parallel_for(0, state.num_envs * cameras, [&](int item) {
    if (recorded_[static_cast<std::size_t>(item / cameras)]) EncodeImage(item / cameras, item % cameras);
  });
  times_.encode_s += SecondsSince(start);
}

void DemoRecorder::SlotStepped(const batch::VecEnv& vec_env, int slot) {
  const engine::BatchState& state = vec_env.state();
  if (!TakesFrame(state, slot)) return;
  RecordingTimes& times = slots_[static_cast<std::size_t>(slot)].times;
  Clock::time_point start = Clock::now();
  proprioception_.UpdateEnv(state, slot);
  CaptureState(slot);
  times.capture_s += SecondsSince(start);
  if (!render_) return;
  start = Clock::now();
  render_->RenderEnv(state, slot);
  times.render_s += SecondsSince(start);
  start = Clock::now();
  for (int camera = 0; camera < static_cast<int>(recording_.cameras.size()); ++camera) EncodeImage(slot, camera);
  times.encode_s += SecondsSince(start);
}

void DemoRecorder::EpisodeEnded(const batch::VecEnv& vec_env, int slot) {
  const engine::BatchState& state = vec_env.state();
  Slot& recording = slots_[static_cast<std::size_t>(slot)];
  const int64_t episode = state.episode[slot];
  times_.capture_s += recording.times.capture_s;
  times_.render_s += recording.times.render_s;
  times_.encode_s += recording.times.encode_s;
  recording.times = RecordingTimes();
  if (state.end[slot] == engine::EpisodeEnd::kSuccess && recording.episode.frames > 0) {
    const Clock::time_point start = Clock::now();
    for (video::EpisodeEncoder& encoder : recording.encoders) recording.episode.videos.push_back(encoder.Finish());
    times_.encode_s += SecondsSince(start);
    finished_[episode] = {std::move(recording.episode), ""};
  } else {
    finished_[episode] = {std::nullopt, engine::ToString(state.end[slot])};
  }
  recording.encoders.clear();
  Release();
}

void DemoRecorder::Release() {
  for (auto next = finished_.find(next_release_); next != finished_.end(); next = finished_.find(next_release_)) {
    if (next->second.episode) {
      keep_(std::move(*next->second.episode));
    } else {
      ++failures_[next->second.end];
    }
    finished_.erase(next);
    ++next_release_;
  }
}

}  // namespace tavis::batch::dataset

// Rollouts as data (`tavis eval --record DIR`): a sink that turns a cell's episodes into dataset
// episodes (dataset::RecordedEpisode, written by the LeRobot writer of `tavis demos`). Unlike a
// demonstration, whose frame t pairs the observation after action t with it (the reference's
// recording), a rollout frame is what the policy had and did at one of its 20 Hz ticks: the
// observation it was given (observation.state and end-effector poses as the driver gives them,
// the neck zeroed under the fixed protocol, and the cameras rendered at that tick by this sink's
// own renderer, so the policy's images are untouched) and the action the env then stepped with.
// Every episode is kept, failed ones too, so an episode of L policy steps (cell::EpisodeRecord::
// length_steps) has L frames and its action rows, served back at 20 Hz, replay it; a tick whose
// action never reached the env (a fault of the served policy, a non-finite action) ends the
// episode without a frame. Episodes are handed on by RecordFinished with the cell's records, so
// in episode order.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "batch/camera_protocol.h"
#include "batch/cell/episode_recorder.h"
#include "batch/dataset/recorded_episode.h"
#include "batch/dataset/video/video_settings.h"
#include "batch/episode_driver.h"
#include "batch/proprioception.h"
#include "batch/scene_render.h"

namespace tavis::batch::rollout {

class RolloutRecorder : public EpisodeSink {
 public:
  using Keep = std::function<void(dataset::RecordedEpisode&&, const cell::EpisodeRecord&)>;

  // Records the env's episodes with `cameras` at video.width x video.height, handing each with its
  // record to `keep` (from RecordFinished).
  RolloutRecorder(const VecEnv& vec_env, CameraProtocol protocol, std::vector<std::string> cameras,
                  dataset::video::VideoSettings video, Keep keep);
  ~RolloutRecorder() override;

  void EpisodeStarted(const VecEnv& vec_env, int slot) override;
  void TickStarting(const VecEnv& vec_env) override;
  void ActionChosen(const VecEnv& vec_env, int slot, const kinematics::Action& action) override;
  void Stepped(const VecEnv& vec_env) override;
  // The per-slot schedule's TickStarting and Stepped: the slot's frame, rendered by its own thread.
  void SlotTickStarting(const VecEnv& vec_env, int slot) override;
  void SlotStepped(const VecEnv& vec_env, int slot) override;
  void EpisodeEnded(const VecEnv& vec_env, int slot) override;
  // Per-slot frames and encoders; episodes wait for their records, in whatever order they end.
  bool works_per_slot() const override { return true; }
  // It renders and encodes the dataset's video: an episode's time split counts it as video.
  LoopPart timed_as() const override { return LoopPart::kVideo; }

  // The cell has recorded `record`: its episode goes to `keep`.
  void RecordFinished(const cell::EpisodeRecord& record);

 private:
  struct Slot;
  // Whether `slot` is observed at the tick about to begin (sets observed_, clears acted_).
  bool Observes(const engine::BatchState& state, int slot);
  // The slot's frame: its action and proprioception, and one camera's image.
  void AppendState(int slot);
  void AppendImage(int slot, int camera);

  std::vector<std::string> cameras_;
  dataset::video::VideoSettings video_;
  Keep keep_;
  int ticks_per_frame_;
  ProprioceptionBatch proprioception_;
  std::unique_ptr<SceneRender> render_;
  std::vector<Slot> slots_;
  std::vector<uint8_t> observed_;                      // (slots) observed at this tick: a frame waits for its action
  std::vector<uint8_t> acted_;                         // (slots) and its action was stepped
  std::map<int64_t, dataset::RecordedEpisode> ended_;  // waiting for their records
};

}  // namespace tavis::batch::rollout

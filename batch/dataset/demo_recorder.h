// The sink that turns scripted-expert episodes into dataset episodes (docs/architecture.md, Design 10): on every
// recorded control tick it takes the action the env stepped with and the observation after the
// step (the reference records frame t as o_{t+1} with a_t, and not the step that ends the
// episode), renders the dataset's cameras with its own renderer, and encodes each camera's frames
// into the episode's video as they come. An episode that succeeds is handed to `keep` in episode
// order (whatever order the slots finish in); the others are dropped and counted.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "batch/dataset/recorded_episode.h"
#include "batch/dataset/video/video_settings.h"
#include "batch/episode_driver.h"
#include "batch/proprioception.h"
#include "batch/scene_render.h"

namespace tavis::batch::dataset {

struct DemoRecording {
  std::vector<std::string> cameras;  // scene camera names, in the dataset's order
  video::VideoSettings video;        // frame size and codec of every camera; fps = control_hz / stride
  int stride = 1;                    // record every stride-th control tick (1: 60 fps, 3: 20 fps)
  int task_index = 0;
};

// Wall time the recorder spent, for the throughput report.
struct RecordingTimes {
  double render_s = 0;
  double encode_s = 0;
  double capture_s = 0;  // state, end-effector poses, actions
};

class DemoRecorder : public batch::EpisodeSink {
 public:
  using Keep = std::function<void(RecordedEpisode&&)>;

  // Records the episodes from `first_episode` on, run on env's slots.
  DemoRecorder(const batch::VecEnv& vec_env, DemoRecording recording, int64_t first_episode, Keep keep);
  ~DemoRecorder() override;

  void EpisodeStarted(const batch::VecEnv& vec_env, int slot) override;
  void ActionChosen(const batch::VecEnv& vec_env, int slot, const kinematics::Action& action) override;
  void Stepped(const batch::VecEnv& vec_env) override;
  // The per-slot schedule's Stepped: the slot's frame, rendered by its own thread.
  void SlotStepped(const batch::VecEnv& vec_env, int slot) override;
  void EpisodeEnded(const batch::VecEnv& vec_env, int slot) override;
  // Per-slot frames and encoders; episodes are handed over in order whatever order they end in.
  bool works_per_slot() const override { return true; }

  // Episodes handed over so far that ended without success, by how they ended. Episodes are
  // handed over in order, so while `keep` runs for episode e this counts the failures before e.
  const std::map<std::string, int64_t>& failures() const { return failures_; }
  const RecordingTimes& times() const { return times_; }

 private:
  struct Slot;
  // Hands the finished episodes to `keep` in episode order, as far as none is missing.
  void Release();
  // Whether the tick just stepped gives `slot` a frame (clears the slot's acted flag).
  bool TakesFrame(const engine::BatchState& state, int slot);
  // The slot's frame: its action and proprioception (proprioception_ updated for it), and the
  // rendered image of one camera.
  void CaptureState(int slot);
  void EncodeImage(int slot, int camera);

  // An episode that has ended: kept (with its recording) or not (how it ended).
  struct Finished {
    std::optional<RecordedEpisode> episode;
    std::string end;
  };

  DemoRecording recording_;
  Keep keep_;
  std::unique_ptr<batch::SceneRender> render_;  // null without cameras
  batch::ProprioceptionBatch proprioception_;
  std::vector<Slot> slots_;
  std::vector<uint8_t> acted_;     // (slots) running when this tick's actions were chosen
  std::vector<uint8_t> recorded_;  // (slots) a frame is taken after this tick's step
  int64_t next_release_;
  std::map<int64_t, Finished> finished_;  // waiting for an earlier episode
  std::map<std::string, int64_t> failures_;
  RecordingTimes times_;
};

}  // namespace tavis::batch::dataset

// Episode videos (`tavis eval --videos N`, a sweep's `videos: N`): a sink that renders the first
// N episodes of a cell with its own renderer, so what the policy sees is untouched, and streams
// every frame to the episode's encoder as it comes. A frame is taken at each of the episode's
// policy ticks (20 Hz: what the policy observed, before it acted) and once more at its end,
// held for one second with the outcome and GALT, which are known only from the episode's record
// (EpisodeVideoRecorder::RecordFinished). An episode of L policy steps (cell::EpisodeRecord::
// length_steps) gives an mp4 of L + kOutcomeFrames frames, or L + 1 PNGs.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "batch/camera_protocol.h"
#include "batch/cell/episode_recorder.h"
#include "batch/dataset/video/episode_encoder.h"
#include "batch/episode_driver.h"
#include "batch/scene_render.h"
#include "render/image_io.h"

namespace tavis::batch::rollout {

enum class VideoFormat { kMp4, kPng };

// "mp4" or "png"; throws std::invalid_argument naming the value otherwise.
VideoFormat ParseVideoFormat(const std::string& text);

struct EpisodeVideoSettings {
  int64_t episodes = 0;              // the first N episodes of the cell; 0: none
  std::vector<std::string> cameras;  // empty: the policy's cameras, then the fixed camera (VideoCameras)
  int tile_width = 320;              // each camera's image in the frame
  int tile_height = 240;
  VideoFormat format = VideoFormat::kMp4;
};

// The end state is held this many frames (one second at 20 fps) with the outcome.
inline constexpr int kOutcomeFrames = 20;

// Throws std::invalid_argument naming the bad value: negative episodes, an unknown or repeated
// camera, a tile size that is not positive and even (yuv420p) or under 64x48.
void ValidateEpisodeVideoSettings(const EpisodeVideoSettings& settings);

// The cameras a video shows: settings.cameras when given; else the cameras the policy sees under
// the protocol (for a policy that takes no images, the scripted expert, those the observation
// contract gives a served policy: head and wrists), then the fixed camera for context.
std::vector<std::string> VideoCameras(const EpisodeVideoSettings& settings,
                                      const std::vector<std::string>& policy_cameras, CameraProtocol protocol);

// The caption's stage: the furthest of the task's stages reached so far (a task declares them
// in the order it is done), e.g. "   stage 3/4 target_grasped"; empty for a task without stages.
std::string StageCaption(const std::vector<cell::StageReached>& stages);

// The file name of episode i's video (mp4) or frame folder (png) inside the videos folder. It is
// written as NAME.partial and renamed to NAME once finished: a video under its name is complete.
std::string EpisodeVideoName(int64_t episode, VideoFormat format);

// True when VIDEOS holds episode i's finished video (or frame folder).
bool HasFinishedVideo(const std::filesystem::path& videos, int64_t episode, VideoFormat format);

class EpisodeVideoRecorder : public EpisodeSink {
 public:
  // Films episodes cell_start .. cell_start + settings.episodes - 1 of the env's cell, showing
  // `cameras`, into folder() (asked at every write: a cell being built beside the one it
  // replaces moves once its first episode is recorded). Throws as ValidateEpisodeVideoSettings.
  EpisodeVideoRecorder(const VecEnv& vec_env, EpisodeVideoSettings settings, std::vector<std::string> cameras,
                       int64_t cell_start, std::function<std::filesystem::path()> folder);
  ~EpisodeVideoRecorder() override;

  void EpisodeStarted(const VecEnv& vec_env, int slot) override;
  void TickStarting(const VecEnv& vec_env) override;
  void ActionChosen(const VecEnv& vec_env, int slot, const kinematics::Action& action) override;
  void EpisodeEnded(const VecEnv& vec_env, int slot) override;
  // An episode's time split counts its rendering and encoding as video.
  LoopPart timed_as() const override { return LoopPart::kVideo; }

  // The cell has recorded `record`: a filmed episode gets its outcome frames and its file is
  // completed. Throws std::runtime_error naming the file when it cannot be written.
  void RecordFinished(const cell::EpisodeRecord& record);

  int64_t videos_written() const { return videos_written_; }
  const std::vector<std::string>& cameras() const { return cameras_; }

 private:
  struct Film;  // one filmed episode: its encoder (mp4) or frame count (png)

  bool Filmed(int64_t episode) const;
  // The tiles of `slot`'s cameras as rendered last, captioned.
  render::RgbImage Frame(int slot, const std::vector<std::string>& caption) const;
  void Write(Film& film, const render::RgbImage& frame);

  EpisodeVideoSettings settings_;
  std::vector<std::string> cameras_;
  int64_t cell_start_;
  std::function<std::filesystem::path()> folder_;
  dataset::video::VideoSettings video_;
  int ticks_per_frame_;  // control ticks per policy tick
  double control_hz_;
  std::unique_ptr<SceneRender> render_;
  std::vector<std::unique_ptr<Film>> running_;      // [slot], null when the slot's episode is not filmed
  std::map<int64_t, std::unique_ptr<Film>> ended_;  // waiting for their records
  std::vector<uint8_t> render_slots_;
  int64_t videos_written_ = 0;
};

}  // namespace tavis::batch::rollout

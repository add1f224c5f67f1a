#include "batch/rollout/cell_recording.h"

#include <stdexcept>

#include "batch/cell/cell_report.h"
#include "batch/dataset/lerobot_features.h"
#include "batch/output/atomic_file.h"
#include "batch/output/setting_error.h"
#include "batch/rollout/observed_cameras.h"
#include "batch/scene_render.h"

namespace tavis::batch::rollout {

void ValidateRolloutDatasetSettings(const RolloutDatasetSettings& settings) {
  CameraSettings cameras;
  cameras.cameras = settings.cameras;
  cameras.width = settings.width;
  cameras.height = settings.height;
  ValidateCameraSettings(cameras);
  for (const std::string& camera : settings.cameras) dataset::CameraVideoKey(camera);
  dataset::video::VideoSettings video;
  video.width = settings.width;
  video.height = settings.height;
  video.fps = 20;
  video.codec = settings.codec;
  const std::string problem = dataset::video::VideoSettingsProblem(video);
  if (!problem.empty()) throw output::SettingError("record_size", problem);
}

CellRecording::CellRecording(RolloutDatasetSettings settings, const cell::EvaluationCellConfig& cell)
    : settings_(std::move(settings)), cell_(cell) {
  ValidateRolloutDatasetSettings(settings_);
}

CellRecording::~CellRecording() = default;

cell::CellSinks CellRecording::Sinks() {
  return [this](const VecEnv& vec_env, const std::vector<std::string>& policy_cameras) -> std::vector<EpisodeSink*> {
    dataset::DatasetLayout layout;
    layout.version = dataset::DatasetVersion::kV30;
    layout.fps = static_cast<int>(vec_env.model().physics.policy_hz + 0.5);
    layout.robot_type = cell_.robot;
    layout.cameras = settings_.cameras.empty() ? ObservedCameras(policy_cameras, cell_.camera) : settings_.cameras;
    layout.video.width = settings_.width;
    layout.video.height = settings_.height;
    layout.video.fps = layout.fps;
    layout.video.codec = settings_.codec;
    for (const kinematics::StateEntry& entry : vec_env.model().robot.observation_state)
      layout.state_names.push_back(entry.name);
    layout.tasks = {vec_env.scenario().class_name};
    writer_ = dataset::MakeDatasetWriter(settings_.root, layout);
    recorder_ = std::make_unique<RolloutRecorder>(
        vec_env, cell_.camera, layout.cameras, layout.video,
        [this](dataset::RecordedEpisode&& episode, const cell::EpisodeRecord& record) {
          std::string line = cell::EpisodeJsonLine(record, cell_.seed) + "\n";
          if (episode.frames > 0) {
            line.insert(1, "\"episode_index\":" + std::to_string(writer_->episodes()) + ",");
            writer_->Add(episode);
          } else {
            line.insert(1, "\"episode_index\":null,");  // it ended before its first action: no frame to store
          }
          rollouts_ += line;
        });
    return {recorder_.get()};
  };
}

void CellRecording::RecordFinished(const cell::EpisodeRecord& record) {
  if (recorder_) recorder_->RecordFinished(record);
}

void CellRecording::Finish() {
  if (!writer_) return;
  output::WriteFileAtomically(settings_.root + "/tavis_rollouts.jsonl", rollouts_);
  writer_->Finish();
}

}  // namespace tavis::batch::rollout

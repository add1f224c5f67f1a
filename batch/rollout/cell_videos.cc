#include "batch/rollout/cell_videos.h"

namespace tavis::batch::rollout {

CellVideos::CellVideos(EpisodeVideoSettings settings, const cell::EvaluationCellConfig& cell,
                       std::function<std::filesystem::path()> folder)
    : settings_(std::move(settings)),
      protocol_(cell.camera),
      cell_start_(cell.episode_start),
      first_to_run_(cell.first_episode),
      folder_(std::move(folder)) {
  ValidateEpisodeVideoSettings(settings_);
}

CellVideos::~CellVideos() = default;

cell::CellSinks CellVideos::Sinks() {
  if (first_to_run_ >= cell_start_ + settings_.episodes) return nullptr;
  return [this](const VecEnv& vec_env, const std::vector<std::string>& policy_cameras) -> std::vector<EpisodeSink*> {
    recorder_ = std::make_unique<EpisodeVideoRecorder>(
        vec_env, settings_, VideoCameras(settings_, policy_cameras, protocol_), cell_start_, folder_);
    return {recorder_.get()};
  };
}

void CellVideos::RecordFinished(const cell::EpisodeRecord& record) {
  if (recorder_) recorder_->RecordFinished(record);
}

std::size_t CellVideos::RecordsKept(const std::vector<cell::EpisodeRecord>& resumed) const {
  for (std::size_t i = 0; i < resumed.size(); ++i) {
    const int64_t episode = resumed[i].episode;
    const bool filmed = episode >= cell_start_ && episode - cell_start_ < settings_.episodes;
    if (filmed && !HasFinishedVideo(folder_(), episode, settings_.format)) return i;
  }
  return resumed.size();
}

}  // namespace tavis::batch::rollout

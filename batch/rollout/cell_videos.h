// An evaluation cell's videos, as `tavis eval` and `tavis sweep` plug them in: the sink factory
// for cell::RunEvaluationCell (cell::CellSinks) and the hook its records go through, so that each filmed
// episode's video is completed with its outcome as soon as its record is written.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <vector>

#include "batch/cell/evaluation_cell.h"
#include "batch/rollout/episode_videos.h"

namespace tavis::batch::rollout {

class CellVideos {
 public:
  // Films the first settings.episodes episodes of `cell` into folder() (asked at every write).
  // Throws std::invalid_argument as ValidateEpisodeVideoSettings.
  CellVideos(EpisodeVideoSettings settings, const cell::EvaluationCellConfig& cell,
             std::function<std::filesystem::path()> folder);
  ~CellVideos();

  // For cell::RunEvaluationCell: no sink when no episode is filmed, or when none of the episodes
  // still to run (a resumed cell) is among the filmed ones.
  cell::CellSinks Sinks();
  // Call with every record the cell writes, before it is written.
  void RecordFinished(const cell::EpisodeRecord& record);
  // For a resumed cell (cell::CellAttachments::records_kept): how many of its records come
  // before the first filmed episode without its finished video in folder().
  std::size_t RecordsKept(const std::vector<cell::EpisodeRecord>& resumed) const;
  int64_t videos_written() const { return recorder_ ? recorder_->videos_written() : 0; }

 private:
  EpisodeVideoSettings settings_;
  CameraProtocol protocol_;
  int64_t cell_start_;
  int64_t first_to_run_;
  std::function<std::filesystem::path()> folder_;
  std::unique_ptr<EpisodeVideoRecorder> recorder_;
};

}  // namespace tavis::batch::rollout

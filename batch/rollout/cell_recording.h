// An evaluation cell's rollouts written as a LeRobot v3.0 dataset (`tavis eval --record DIR`),
// through the dataset writer of `tavis demos`: every episode of the cell, in episode order, as
// RolloutRecorder records it (the policy's observations and actions at 20 fps), the task's
// class name as LeRobot's task, and beside the dataset DIR/tavis_rollouts.jsonl: per dataset
// episode its episode_index and the cell's record of it (success, end, length, GALT: the line
// episodes.jsonl holds). The metadata is written by Finish, meta/info.json last: a dataset
// without it is unfinished.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "batch/cell/evaluation_cell.h"
#include "batch/dataset/lerobot_writer.h"
#include "batch/dataset/video/video_settings.h"
#include "batch/rollout/rollout_recorder.h"

namespace tavis::batch::rollout {

struct RolloutDatasetSettings {
  std::string root;                  // the dataset's folder (new or empty; the caller prepares it)
  std::vector<std::string> cameras;  // empty: ObservedCameras
  int width = 320;                   // the observation contract's size
  int height = 240;
  dataset::video::VideoCodec codec = dataset::video::VideoCodec::kH264;
};

// Throws std::invalid_argument naming a bad camera or size (a camera without a dataset key, an
// odd size).
void ValidateRolloutDatasetSettings(const RolloutDatasetSettings& settings);

class CellRecording {
 public:
  // Records every episode `cell` runs. Throws as ValidateRolloutDatasetSettings.
  CellRecording(RolloutDatasetSettings settings, const cell::EvaluationCellConfig& cell);
  ~CellRecording();

  // For cell::RunEvaluationCell; opens the dataset writer.
  cell::CellSinks Sinks();
  // Call with every record the cell writes.
  void RecordFinished(const cell::EpisodeRecord& record);
  // Writes the metadata; the dataset is complete.
  void Finish();

  int64_t episodes() const { return writer_ ? writer_->episodes() : 0; }
  int64_t frames() const { return writer_ ? writer_->frames() : 0; }

 private:
  RolloutDatasetSettings settings_;
  cell::EvaluationCellConfig cell_;
  std::unique_ptr<dataset::DatasetWriter> writer_;
  std::unique_ptr<RolloutRecorder> recorder_;
  std::string rollouts_;  // tavis_rollouts.jsonl's lines
};

}  // namespace tavis::batch::rollout

// Kept episodes made durable the moment they are kept, so an interrupted `tavis demos` resumes
// after the last of them instead of starting over (the dataset's own files are complete only at
// the end). Episode n of the dataset lives in SPOOL/episode_<n>/: data.parquet (its frames, as
// the dataset stores them), one CAMERA.packets per camera (its encoded video as the encoder made
// it, appended later without decoding: encoded_episode_file.h) and episode.json, written last, so an episode is in the
// spool once episode.json exists. progress.json says where the recording stands. The spool is removed once the dataset
// is finished.
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "batch/dataset/lerobot_features.h"
#include "batch/dataset/recorded_episode.h"

namespace tavis::batch::dataset {

// A kept episode as the spool holds it, with what a resumed recording needs to report the same
// counts as an uninterrupted one.
struct SpooledEpisode {
  RecordedEpisode episode;
  // How the task's episodes before this one that failed ended (not written to the dataset).
  std::map<std::string, int64_t> task_failures_before;
};

class EpisodeSpool {
 public:
  // Creates `dir` if needed.
  EpisodeSpool(std::string dir, DatasetLayout layout);

  // Stores `episode` as dataset episode count(), with its task's failures before it.
  void Save(const RecordedEpisode& episode, const std::map<std::string, int64_t>& task_failures_before);
  // Episodes 0 .. count() - 1 are complete in the spool (counted when constructed, then by Save).
  int64_t count() const { return count_; }
  // Episode n as Save received it (videos as packets, image statistics as histograms). Throws
  // std::runtime_error naming the file and what is wrong when it is missing, unreadable or damaged.
  SpooledEpisode Load(int64_t n) const;

  // The recording's progress (written atomically; null when none was written; a file that is
  // not a JSON object is an error naming it).
  void SaveProgress(const nlohmann::json& progress) const;
  nlohmann::json LoadProgress() const;

  // Removes the spool's folder.
  void Remove() const;
  const std::string& dir() const { return dir_; }

 private:
  std::string EpisodeDir(int64_t n) const;

  std::string dir_;
  DatasetLayout layout_;
  int64_t count_ = 0;
};

}  // namespace tavis::batch::dataset

// The v2.1 layout (lerobot_writer.h): one file per episode, JSON-lines metadata.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "batch/dataset/episode_rows.h"
#include "batch/dataset/lerobot_stats.h"
#include "batch/dataset/lerobot_writer.h"
#include "batch/dataset/parquet/parquet_writer.h"
#include "batch/dataset/video/video_writer.h"
#include "batch/output/atomic_file.h"

namespace tavis::batch::dataset {
namespace {

constexpr int64_t kChunksSize = 1000;

class V21Writer : public DatasetWriter {
 public:
  V21Writer(std::string root, DatasetLayout layout) : root_(std::move(root)), layout_(std::move(layout)) {
    std::filesystem::create_directories(root_ + "/meta");
  }

  void Add(const RecordedEpisode& episode) override {
    const int64_t index = episodes_;
    char chunk[32], name[32];
    std::snprintf(chunk, sizeof chunk, "chunk-%03lld", static_cast<long long>(index / kChunksSize));
    std::snprintf(name, sizeof name, "episode_%06lld", static_cast<long long>(index));
    const std::filesystem::path data = std::filesystem::path(root_) / "data" / chunk / (std::string(name) + ".parquet");
    std::filesystem::create_directories(data.parent_path());
    parquet::ParquetWriter writer(data.string(), DataColumns(layout_));
    WriteEpisodeRows(writer, episode, layout_, index, frames_);
    writer.Close();
    for (std::size_t camera = 0; camera < layout_.cameras.size(); ++camera) {
      const std::filesystem::path video = std::filesystem::path(root_) / "videos" / chunk /
                                          CameraVideoKey(layout_.cameras[camera]) / (std::string(name) + ".mp4");
      std::filesystem::create_directories(video.parent_path());
      video::VideoSettings settings = layout_.video;
      settings.fps = layout_.fps;
      video::Mp4VideoWriter file(video.string(), settings);
      file.AppendEpisode(episode.videos[camera]);
      file.Close();
    }
    const DatasetStats stats = EpisodeStats(episode, layout_, index, frames_);
    stats_.Merge(stats);
    episodes_text_ += nlohmann::json{{"episode_index", index},
                                     {"tasks", {layout_.tasks[static_cast<std::size_t>(episode.task_index)]}},
                                     {"length", episode.frames}}
                          .dump() +
                      "\n";
    stats_text_ += nlohmann::json{{"episode_index", index}, {"stats", stats.ToJson()}}.dump() + "\n";
    ++episodes_;
    frames_ += episode.frames;
  }

  void Finish() override {
    if (episodes_ == 0) throw std::runtime_error("dataset " + root_ + ": no episode to write");
    std::string tasks;
    for (std::size_t i = 0; i < layout_.tasks.size(); ++i) {
      tasks += nlohmann::json{{"task_index", i}, {"task", layout_.tasks[i]}}.dump() + "\n";
    }
    batch::output::WriteFileAtomically(root_ + "/meta/tasks.jsonl", tasks);
    batch::output::WriteFileAtomically(root_ + "/meta/episodes.jsonl", episodes_text_);
    batch::output::WriteFileAtomically(root_ + "/meta/episodes_stats.jsonl", stats_text_);
    batch::output::WriteFileAtomically(root_ + "/meta/stats.json", stats_.ToJson().dump(2) + "\n");
    const nlohmann::json info = {
        {"codebase_version", "v2.1"},
        {"robot_type", layout_.robot_type},
        {"total_episodes", episodes_},
        {"total_frames", frames_},
        {"total_tasks", layout_.tasks.size()},
        {"total_videos", episodes_ * static_cast<int64_t>(layout_.cameras.size())},
        {"total_chunks", (episodes_ + kChunksSize - 1) / kChunksSize},
        {"chunks_size", kChunksSize},
        {"fps", layout_.fps},
        {"splits", {{"train", "0:" + std::to_string(episodes_)}}},
        {"data_path", "data/chunk-{episode_chunk:03d}/episode_{episode_index:06d}.parquet"},
        {"video_path",
         layout_.cameras.empty()
             ? nlohmann::json()
             : nlohmann::json("videos/chunk-{episode_chunk:03d}/{video_key}/episode_{episode_index:06d}.mp4")},
        {"features", FeaturesJson(layout_)}};
    batch::output::WriteFileAtomically(root_ + "/meta/info.json", info.dump(2) + "\n");
  }

  int64_t episodes() const override { return episodes_; }
  int64_t frames() const override { return frames_; }

 private:
  std::string root_;
  DatasetLayout layout_;
  DatasetStats stats_;
  std::string episodes_text_, stats_text_;
  int64_t episodes_ = 0;
  int64_t frames_ = 0;
};

}  // namespace

std::unique_ptr<DatasetWriter> MakeV21Writer(const std::string& root, const DatasetLayout& layout) {
  return std::make_unique<V21Writer>(root, layout);
}

}  // namespace tavis::batch::dataset

// The v3.0 layout (lerobot_writer.h).
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/dataset/episode_rows.h"
#include "batch/dataset/lerobot_stats.h"
#include "batch/dataset/lerobot_writer.h"
#include "batch/dataset/parquet/parquet_writer.h"
#include "batch/dataset/video/video_writer.h"
#include "batch/output/atomic_file.h"

namespace tavis::batch::dataset {
namespace {

// LeRobot's default (lerobot-v3-format.md 1-2).
constexpr int kChunksSize = 1000;
constexpr double kMegabyte = 1024.0 * 1024.0;

// info.json's file size limits: LeRobot 0.4.3 reads them as ints, so whole numbers are written so.
nlohmann::json Megabytes(double size) {
  return size == static_cast<double>(static_cast<int64_t>(size)) ? nlohmann::json(static_cast<int64_t>(size))
                                                                 : nlohmann::json(size);
}

// A (chunk, file) cursor, advanced as LeRobot's update_chunk_file_indices does.
struct FileIndex {
  int chunk = 0;
  int file = 0;

  void Advance() {
    if (file == kChunksSize - 1) {
      file = 0;
      ++chunk;
    } else {
      ++file;
    }
  }
};

std::string Numbered(const std::string& prefix, FileIndex index, const char* extension) {
  char path[64];
  std::snprintf(path, sizeof path, "chunk-%03d/file-%03d.%s", index.chunk, index.file, extension);
  return prefix + path;
}

// Where one episode lives, for its row in meta/episodes.
struct EpisodeRow {
  int64_t length = 0;
  int task_index = 0;
  FileIndex data;
  int64_t from_index = 0;
  std::vector<FileIndex> video;  // per camera
  std::vector<double> from_timestamp, to_timestamp;
  std::map<std::string, FeatureStats> numeric_stats, image_stats;  // by feature
};

// One camera's current mp4 file.
struct CameraFile {
  FileIndex index;
  std::unique_ptr<video::Mp4VideoWriter> writer;
};

class V30Writer : public DatasetWriter {
 public:
  V30Writer(std::string root, DatasetLayout layout)
      : root_(std::move(root)), layout_(std::move(layout)), cameras_(layout_.cameras.size()) {
    std::filesystem::create_directories(root_ + "/meta");
  }

  void Add(const RecordedEpisode& episode) override {
    EpisodeRow row;
    row.length = episode.frames;
    row.task_index = episode.task_index;
    row.from_index = frames_;
    row.data = DataFileFor(episode.frames);
    WriteEpisodeRows(*data_, episode, layout_, episodes(), frames_);
    for (std::size_t camera = 0; camera < cameras_.size(); ++camera) {
      CameraFile& file = VideoFileFor(camera, episode.videos[camera].bytes());
      const double from = static_cast<double>(file.writer->frames_written()) / layout_.fps;
      file.writer->AppendEpisode(episode.videos[camera]);
      row.video.push_back(file.index);
      row.from_timestamp.push_back(from);
      row.to_timestamp.push_back(static_cast<double>(file.writer->frames_written()) / layout_.fps);
    }
    const DatasetStats stats = EpisodeStats(episode, layout_, episodes(), frames_);
    for (const auto& [feature, values] : stats.numeric) row.numeric_stats.emplace(feature, values.Compute());
    for (const auto& [feature, values] : stats.images) row.image_stats.emplace(feature, values.Compute());
    stats_.Merge(stats);
    frames_ += episode.frames;
    rows_.push_back(std::move(row));
  }

  void Finish() override {
    if (rows_.empty()) throw std::runtime_error("dataset " + root_ + ": no episode to write");
    if (data_) data_->Close();
    for (CameraFile& file : cameras_) {
      if (file.writer) file.writer->Close();
    }
    WriteEpisodesTable();
    WriteTasksTable();
    batch::output::WriteFileAtomically(root_ + "/meta/stats.json", stats_.ToJson().dump(2) + "\n");
    batch::output::WriteFileAtomically(root_ + "/meta/info.json", InfoJson().dump(2) + "\n");
  }

  int64_t episodes() const override { return static_cast<int64_t>(rows_.size()); }
  int64_t frames() const override { return frames_; }

 private:
  // The data file the next episode of `frames` frames goes to: a new one when the current file
  // would reach the size limit with it (estimated from its bytes per frame so far).
  FileIndex DataFileFor(int64_t frames) {
    if (data_) {
      const double per_frame = static_cast<double>(data_->bytes_written()) / static_cast<double>(data_->num_rows());
      if ((static_cast<double>(data_->bytes_written()) + per_frame * static_cast<double>(frames)) / kMegabyte >=
          layout_.data_files_size_mb) {
        data_->Close();
        data_.reset();
        data_index_.Advance();
      }
    }
    if (!data_) {
      const std::string path = root_ + "/" + Numbered("data/", data_index_, "parquet");
      std::filesystem::create_directories(std::filesystem::path(path).parent_path());
      data_ = std::make_unique<parquet::ParquetWriter>(path, DataColumns(layout_));
    }
    return data_index_;
  }

  CameraFile& VideoFileFor(std::size_t camera, int64_t episode_bytes) {
    CameraFile& file = cameras_[camera];
    if (file.writer &&
        static_cast<double>(file.writer->bytes_written() + episode_bytes) / kMegabyte >= layout_.video_files_size_mb) {
      file.writer->Close();
      file.writer.reset();
      file.index.Advance();
    }
    if (!file.writer) {
      const std::string path =
          root_ + "/" + Numbered("videos/" + CameraVideoKey(layout_.cameras[camera]) + "/", file.index, "mp4");
      std::filesystem::create_directories(std::filesystem::path(path).parent_path());
      video::VideoSettings settings = layout_.video;
      settings.fps = layout_.fps;
      file.writer = std::make_unique<video::Mp4VideoWriter>(path, settings);
    }
    return file;
  }

  void WriteEpisodesTable() const {
    std::vector<parquet::ColumnSpec> columns = {
        parquet::ColumnSpec::Scalar("episode_index", parquet::ValueType::kInt64),
        parquet::ColumnSpec::List("tasks", parquet::ValueType::kString),
        parquet::ColumnSpec::Scalar("length", parquet::ValueType::kInt64),
        parquet::ColumnSpec::Scalar("data/chunk_index", parquet::ValueType::kInt64),
        parquet::ColumnSpec::Scalar("data/file_index", parquet::ValueType::kInt64),
        parquet::ColumnSpec::Scalar("dataset_from_index", parquet::ValueType::kInt64),
        parquet::ColumnSpec::Scalar("dataset_to_index", parquet::ValueType::kInt64)};
    for (const std::string& camera : layout_.cameras) {
      const std::string prefix = "videos/" + CameraVideoKey(camera) + "/";
      columns.push_back(parquet::ColumnSpec::Scalar(prefix + "chunk_index", parquet::ValueType::kInt64));
      columns.push_back(parquet::ColumnSpec::Scalar(prefix + "file_index", parquet::ValueType::kInt64));
      columns.push_back(parquet::ColumnSpec::Scalar(prefix + "from_timestamp", parquet::ValueType::kDouble));
      columns.push_back(parquet::ColumnSpec::Scalar(prefix + "to_timestamp", parquet::ValueType::kDouble));
    }
    for (const auto& [feature, stats] : rows_.front().numeric_stats) {
      for (const std::string& stat : kStatNames) {
        const bool count = stat == "count";
        columns.push_back(parquet::ColumnSpec::List("stats/" + feature + "/" + stat,
                                                    count ? parquet::ValueType::kInt64 : parquet::ValueType::kDouble,
                                                    {count ? 1 : stats.min.size()}));
      }
    }
    for (const auto& [feature, stats] : rows_.front().image_stats) {
      for (const std::string& stat : kStatNames) {
        const bool count = stat == "count";
        columns.push_back(
            count ? parquet::ColumnSpec::List("stats/" + feature + "/count", parquet::ValueType::kInt64, {1})
                  : parquet::ColumnSpec::List("stats/" + feature + "/" + stat, parquet::ValueType::kDouble, {3, 1, 1}));
      }
    }
    columns.push_back(parquet::ColumnSpec::Scalar("meta/episodes/chunk_index", parquet::ValueType::kInt64));
    columns.push_back(parquet::ColumnSpec::Scalar("meta/episodes/file_index", parquet::ValueType::kInt64));

    const std::string path = root_ + "/meta/episodes/chunk-000/file-000.parquet";
    std::filesystem::create_directories(std::filesystem::path(path).parent_path());
    parquet::ParquetWriter writer(path, columns);
    parquet::RowGroupBuilder rows = writer.NewRowGroup(rows_.size());
    const auto column = [this](auto value_of) {
      std::vector<decltype(value_of(rows_.front()))> values;
      for (const EpisodeRow& row : rows_) values.push_back(value_of(row));
      return values;
    };
    std::vector<int64_t> episode_index;
    for (std::size_t i = 0; i < rows_.size(); ++i) episode_index.push_back(static_cast<int64_t>(i));
    rows.Add("episode_index", episode_index);
    std::vector<std::string> tasks;
    for (const EpisodeRow& row : rows_) tasks.push_back(layout_.tasks[static_cast<std::size_t>(row.task_index)]);
    rows.AddList("tasks", tasks, std::vector<std::size_t>(rows_.size(), 1));
    rows.Add("length", column([](const EpisodeRow& row) { return row.length; }));
    rows.Add("data/chunk_index", column([](const EpisodeRow& row) { return int64_t{row.data.chunk}; }));
    rows.Add("data/file_index", column([](const EpisodeRow& row) { return int64_t{row.data.file}; }));
    rows.Add("dataset_from_index", column([](const EpisodeRow& row) { return row.from_index; }));
    rows.Add("dataset_to_index", column([](const EpisodeRow& row) { return row.from_index + row.length; }));
    for (std::size_t camera = 0; camera < layout_.cameras.size(); ++camera) {
      const std::string prefix = "videos/" + CameraVideoKey(layout_.cameras[camera]) + "/";
      rows.Add(prefix + "chunk_index",
               column([camera](const EpisodeRow& row) { return int64_t{row.video[camera].chunk}; }));
      rows.Add(prefix + "file_index",
               column([camera](const EpisodeRow& row) { return int64_t{row.video[camera].file}; }));
      rows.Add(prefix + "from_timestamp",
               column([camera](const EpisodeRow& row) { return row.from_timestamp[camera]; }));
      rows.Add(prefix + "to_timestamp", column([camera](const EpisodeRow& row) { return row.to_timestamp[camera]; }));
    }
    AddStatsColumns(rows);
    rows.Add("meta/episodes/chunk_index", std::vector<int64_t>(rows_.size(), 0));
    rows.Add("meta/episodes/file_index", std::vector<int64_t>(rows_.size(), 0));
    writer.WriteRowGroup(rows);
    writer.Close();
  }

  // stats/<feature>/<stat> of every episode, in the columns' order.
  void AddStatsColumns(parquet::RowGroupBuilder& rows) const {
    const auto add = [&](const std::string& feature, std::map<std::string, FeatureStats> EpisodeRow::*table) {
      for (const std::string& stat : kStatNames) {
        const std::string name = "stats/" + feature + "/" + stat;
        if (stat == "count") {
          std::vector<int64_t> counts;
          for (const EpisodeRow& row : rows_) counts.push_back((row.*table).at(feature).count);
          rows.AddList(name, counts);
          continue;
        }
        std::vector<double> values;
        for (const EpisodeRow& row : rows_) {
          const std::vector<double> entry = StatValues((row.*table).at(feature), stat);
          values.insert(values.end(), entry.begin(), entry.end());
        }
        rows.AddList(name, values);
      }
    };
    for (const auto& [feature, unused] : rows_.front().numeric_stats) add(feature, &EpisodeRow::numeric_stats);
    for (const auto& [feature, unused] : rows_.front().image_stats) add(feature, &EpisodeRow::image_stats);
  }

  // task_index -> task, with the pandas metadata that makes `task` the DataFrame's index
  // (lerobot-v3-format.md 3.3).
  void WriteTasksTable() const {
    parquet::ParquetWriterOptions options;
    options.key_value_metadata = {
        {"pandas",
         R"({"index_columns": ["task"], "column_indexes": [{"name": null, "field_name": null, "pandas_type": "unicode", )"
         R"("numpy_type": "object", "metadata": {"encoding": "UTF-8"}}], "columns": [{"name": "task_index", )"
         R"("field_name": "task_index", "pandas_type": "int64", "numpy_type": "int64", "metadata": null}, {"name": "task", )"
         R"("field_name": "task", "pandas_type": "unicode", "numpy_type": "object", "metadata": null}]})"}};
    parquet::ParquetWriter writer(root_ + "/meta/tasks.parquet",
                                  {parquet::ColumnSpec::Scalar("task_index", parquet::ValueType::kInt64),
                                   parquet::ColumnSpec::Scalar("task", parquet::ValueType::kString)},
                                  options);
    parquet::RowGroupBuilder rows = writer.NewRowGroup(layout_.tasks.size());
    std::vector<int64_t> index;
    for (std::size_t i = 0; i < layout_.tasks.size(); ++i) index.push_back(static_cast<int64_t>(i));
    rows.Add("task_index", index);
    rows.Add("task", layout_.tasks);
    writer.WriteRowGroup(rows);
    writer.Close();
  }

  nlohmann::json InfoJson() const {
    return {
        {"codebase_version", "v3.0"},
        {"robot_type", layout_.robot_type},
        {"total_episodes", episodes()},
        {"total_frames", frames_},
        {"total_tasks", layout_.tasks.size()},
        {"chunks_size", kChunksSize},
        {"data_files_size_in_mb", Megabytes(layout_.data_files_size_mb)},
        {"video_files_size_in_mb", Megabytes(layout_.video_files_size_mb)},
        {"fps", layout_.fps},
        {"splits", {{"train", "0:" + std::to_string(episodes())}}},
        {"data_path", "data/chunk-{chunk_index:03d}/file-{file_index:03d}.parquet"},
        {"video_path", layout_.cameras.empty()
                           ? nlohmann::json()
                           : nlohmann::json("videos/{video_key}/chunk-{chunk_index:03d}/file-{file_index:03d}.mp4")},
        {"features", FeaturesJson(layout_)}};
  }

  std::string root_;
  DatasetLayout layout_;
  std::unique_ptr<parquet::ParquetWriter> data_;
  FileIndex data_index_;
  std::vector<CameraFile> cameras_;
  std::vector<EpisodeRow> rows_;
  DatasetStats stats_;
  int64_t frames_ = 0;
};

}  // namespace

std::unique_ptr<DatasetWriter> MakeV30Writer(const std::string& root, const DatasetLayout& layout) {
  return std::make_unique<V30Writer>(root, layout);
}

}  // namespace tavis::batch::dataset

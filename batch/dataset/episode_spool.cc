#include "batch/dataset/episode_spool.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "batch/dataset/episode_rows.h"
#include "batch/dataset/parquet/parquet_reader.h"
#include "batch/dataset/parquet/parquet_writer.h"
#include "batch/dataset/video/encoded_episode_file.h"
#include "batch/output/atomic_file.h"
#include "batch/output/json_error_text.h"

namespace tavis::batch::dataset {
namespace {

nlohmann::json ReadJson(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& error) {
    throw std::runtime_error(path.string() +
                             ": damaged spool file, not valid JSON: " + batch::output::JsonErrorText(error.what()));
  }
}

// record[key] as T, or an error naming the file, the key and what is wrong with it.
template <typename T>
T Field(const nlohmann::json& record, const char* key, const std::filesystem::path& path) {
  if (!record.is_object() || !record.contains(key)) {
    throw std::runtime_error(path.string() + ": damaged spool file, no \"" + key + "\"");
  }
  try {
    return record.at(key).get<T>();
  } catch (const nlohmann::json::exception& error) {
    throw std::runtime_error(path.string() + ": damaged spool file, \"" + key + "\" is " +
                             record.at(key).dump(-1).substr(0, 80) + ": " + batch::output::JsonErrorText(error.what()));
  }
}

std::vector<float> ReadVectors(const parquet::ParquetReader& reader, const std::string& column) {
  return reader.ReadListColumn<float>(column).values;
}

}  // namespace

EpisodeSpool::EpisodeSpool(std::string dir, DatasetLayout layout) : dir_(std::move(dir)), layout_(std::move(layout)) {
  std::filesystem::create_directories(dir_);
  while (std::filesystem::exists(std::filesystem::path(EpisodeDir(count_)) / "episode.json")) ++count_;
}

std::string EpisodeSpool::EpisodeDir(int64_t n) const {
  char name[32];
  std::snprintf(name, sizeof name, "episode_%06lld", static_cast<long long>(n));
  return dir_ + "/" + name;
}

void EpisodeSpool::Save(const RecordedEpisode& episode, const std::map<std::string, int64_t>& task_failures_before) {
  const std::string dir = EpisodeDir(count_);
  std::filesystem::remove_all(dir);  // what an interrupted Save left
  std::filesystem::create_directories(dir);
  parquet::ParquetWriter data(dir + "/data.parquet", DataColumns(layout_));
  WriteEpisodeRows(data, episode, layout_, count_, 0);
  data.Close();
  nlohmann::json histograms = nlohmann::json::array();
  for (std::size_t camera = 0; camera < layout_.cameras.size(); ++camera) {
    video::SaveEncodedEpisode(episode.videos[camera], dir + "/" + layout_.cameras[camera] + ".packets");
    histograms.push_back(
        {{"frames", episode.image_stats[camera].frames()}, {"histogram", episode.image_stats[camera].histogram()}});
  }
  const nlohmann::json record = {{"source_episode", episode.source_episode},
                                 {"task_index", episode.task_index},
                                 {"prompt", episode.prompt},
                                 {"frames", episode.frames},
                                 {"image_histograms", histograms},
                                 {"task_failures_before", task_failures_before}};
  batch::output::WriteFileAtomically(dir + "/episode.json", record.dump() + "\n");
  ++count_;
}

SpooledEpisode EpisodeSpool::Load(int64_t n) const {
  const std::string dir = EpisodeDir(n);
  const std::filesystem::path record_path = dir + "/episode.json";
  const nlohmann::json record = ReadJson(record_path);
  SpooledEpisode spooled;
  RecordedEpisode& episode = spooled.episode;
  episode.source_episode = Field<int64_t>(record, "source_episode", record_path);
  episode.task_index = Field<int>(record, "task_index", record_path);
  if (episode.task_index < 0 || static_cast<std::size_t>(episode.task_index) >= layout_.tasks.size()) {
    throw std::runtime_error(record_path.string() + ": damaged spool file, \"task_index\" " +
                             std::to_string(episode.task_index) + " is not one of the recording's " +
                             std::to_string(layout_.tasks.size()) + " tasks");
  }
  episode.prompt = Field<std::string>(record, "prompt", record_path);
  episode.frames = Field<int64_t>(record, "frames", record_path);
  // Spools of earlier versions did not keep the failures: counted from this episode on.
  if (record.contains("task_failures_before")) {
    spooled.task_failures_before = Field<std::map<std::string, int64_t>>(record, "task_failures_before", record_path);
  }
  const parquet::ParquetReader data(dir + "/data.parquet");
  episode.action = ReadVectors(data, "action");
  episode.state = ReadVectors(data, "observation.state");
  episode.left_eef_pos = ReadVectors(data, "observation.left_eef_pos");
  episode.left_eef_quat = ReadVectors(data, "observation.left_eef_quat");
  episode.right_eef_pos = ReadVectors(data, "observation.right_eef_pos");
  episode.right_eef_quat = ReadVectors(data, "observation.right_eef_quat");
  if (data.num_rows() != episode.frames) {
    throw std::runtime_error(dir + ": data.parquet has " + std::to_string(data.num_rows()) +
                             " frames, episode.json says " + std::to_string(episode.frames));
  }
  const nlohmann::json histograms = Field<nlohmann::json>(record, "image_histograms", record_path);
  if (!histograms.is_array() || histograms.size() != layout_.cameras.size()) {
    throw std::runtime_error(record_path.string() +
                             ": damaged spool file, \"image_histograms\" needs one entry per camera (" +
                             std::to_string(layout_.cameras.size()) + ")");
  }
  video::VideoSettings settings = layout_.video;
  settings.fps = layout_.fps;
  for (std::size_t camera = 0; camera < layout_.cameras.size(); ++camera) {
    episode.videos.push_back(video::LoadEncodedEpisode(dir + "/" + layout_.cameras[camera] + ".packets", settings));
    episode.image_stats.push_back(
        ImageStats::FromHistogram(Field<int64_t>(histograms[camera], "frames", record_path),
                                  Field<ImageStats::Histogram>(histograms[camera], "histogram", record_path)));
  }
  return spooled;
}

void EpisodeSpool::SaveProgress(const nlohmann::json& progress) const {
  batch::output::WriteFileAtomically(dir_ + "/progress.json", progress.dump(2) + "\n");
}

nlohmann::json EpisodeSpool::LoadProgress() const {
  const std::filesystem::path path = dir_ + "/progress.json";
  if (!std::filesystem::exists(path)) return nlohmann::json();
  nlohmann::json progress = ReadJson(path);
  if (!progress.is_object()) throw std::runtime_error(path.string() + ": damaged spool file, not a JSON object");
  return progress;
}

void EpisodeSpool::Remove() const { std::filesystem::remove_all(dir_); }

}  // namespace tavis::batch::dataset

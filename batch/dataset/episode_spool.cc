#include "batch/dataset/episode_spool.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "batch/atomic_file.h"
#include "batch/dataset/episode_rows.h"
#include "batch/dataset/parquet/parquet_reader.h"
#include "batch/dataset/parquet/parquet_writer.h"
#include "batch/dataset/video/encoded_episode_file.h"

namespace tavis::dataset {
namespace {

nlohmann::json ReadJson(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& error) {
    throw std::runtime_error(path.string() + ": " + error.what());
  }
}

std::vector<float> ReadVectors(const ParquetReader& reader, const std::string& column) {
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

void EpisodeSpool::Save(const RecordedEpisode& episode) {
  const std::string dir = EpisodeDir(count_);
  std::filesystem::remove_all(dir);  // what an interrupted Save left
  std::filesystem::create_directories(dir);
  ParquetWriter data(dir + "/data.parquet", DataColumns(layout_));
  WriteEpisodeRows(data, episode, layout_, count_, 0);
  data.Close();
  nlohmann::json histograms = nlohmann::json::array();
  for (std::size_t camera = 0; camera < layout_.cameras.size(); ++camera) {
    SaveEncodedEpisode(episode.videos[camera], dir + "/" + layout_.cameras[camera] + ".packets");
    histograms.push_back({{"frames", episode.image_stats[camera].frames()}, {"histogram", episode.image_stats[camera].histogram()}});
  }
  const nlohmann::json record = {{"source_episode", episode.source_episode},
                                 {"task_index", episode.task_index},
                                 {"prompt", episode.prompt},
                                 {"frames", episode.frames},
                                 {"image_histograms", histograms}};
  batch::WriteFileAtomically(dir + "/episode.json", record.dump() + "\n");
  ++count_;
}

RecordedEpisode EpisodeSpool::Load(int64_t n) const {
  const std::string dir = EpisodeDir(n);
  const nlohmann::json record = ReadJson(dir + "/episode.json");
  RecordedEpisode episode;
  episode.source_episode = record.at("source_episode").get<int64_t>();
  episode.task_index = record.at("task_index").get<int>();
  episode.prompt = record.at("prompt").get<std::string>();
  episode.frames = record.at("frames").get<int64_t>();
  const ParquetReader data(dir + "/data.parquet");
  episode.action = ReadVectors(data, "action");
  episode.state = ReadVectors(data, "observation.state");
  episode.left_eef_pos = ReadVectors(data, "observation.left_eef_pos");
  episode.left_eef_quat = ReadVectors(data, "observation.left_eef_quat");
  episode.right_eef_pos = ReadVectors(data, "observation.right_eef_pos");
  episode.right_eef_quat = ReadVectors(data, "observation.right_eef_quat");
  if (data.num_rows() != episode.frames) {
    throw std::runtime_error(dir + ": data.parquet has " + std::to_string(data.num_rows()) + " frames, episode.json says " +
                             std::to_string(episode.frames));
  }
  const nlohmann::json& histograms = record.at("image_histograms");
  VideoSettings settings = layout_.video;
  settings.fps = layout_.fps;
  for (std::size_t camera = 0; camera < layout_.cameras.size(); ++camera) {
    episode.videos.push_back(LoadEncodedEpisode(dir + "/" + layout_.cameras[camera] + ".packets", settings));
    episode.image_stats.push_back(ImageStats::FromHistogram(histograms.at(camera).at("frames").get<int64_t>(),
                                                            histograms.at(camera).at("histogram").get<ImageStats::Histogram>()));
  }
  return episode;
}

void EpisodeSpool::SaveProgress(const nlohmann::json& progress) const {
  batch::WriteFileAtomically(dir_ + "/progress.json", progress.dump(2) + "\n");
}

nlohmann::json EpisodeSpool::LoadProgress() const {
  const std::filesystem::path path = dir_ + "/progress.json";
  return std::filesystem::exists(path) ? ReadJson(path) : nlohmann::json();
}

void EpisodeSpool::Remove() const { std::filesystem::remove_all(dir_); }

}  // namespace tavis::dataset

#include "batch/dataset/lerobot_stats.h"

#include <stdexcept>

namespace tavis::batch::dataset {
namespace {

const std::vector<float>& VectorOf(const RecordedEpisode& episode, const std::string& feature) {
  if (feature == "action") return episode.action;
  if (feature == "observation.state") return episode.state;
  if (feature == "observation.left_eef_pos") return episode.left_eef_pos;
  if (feature == "observation.left_eef_quat") return episode.left_eef_quat;
  if (feature == "observation.right_eef_pos") return episode.right_eef_pos;
  if (feature == "observation.right_eef_quat") return episode.right_eef_quat;
  throw std::logic_error("no vector feature " + feature);
}

nlohmann::json StatsJson(const FeatureStats& stats, bool image) {
  nlohmann::json json = nlohmann::json::object();
  for (const std::string& stat : kStatNames) {
    if (stat == "count") {
      json[stat] = {stats.count};
      continue;
    }
    const std::vector<double> values = StatValues(stats, stat);
    if (!image) {
      json[stat] = values;
      continue;
    }
    nlohmann::json channels = nlohmann::json::array();
    for (double value : values) channels.push_back({{value}});  // (3, 1, 1)
    json[stat] = channels;
  }
  return json;
}

}  // namespace

std::vector<double> StatValues(const FeatureStats& stats, const std::string& stat) {
  if (stat == "min") return stats.min;
  if (stat == "max") return stats.max;
  if (stat == "mean") return stats.mean;
  if (stat == "std") return stats.std;
  if (stat == "count") return {static_cast<double>(stats.count)};
  if (stat == "q01") return stats.q01;
  if (stat == "q10") return stats.q10;
  if (stat == "q50") return stats.q50;
  if (stat == "q90") return stats.q90;
  if (stat == "q99") return stats.q99;
  throw std::logic_error("no statistic " + stat);
}

void DatasetStats::Merge(const DatasetStats& other) {
  for (const auto& [name, stats] : other.numeric) {
    auto found = numeric.find(name);
    if (found == numeric.end()) {
      numeric.emplace(name, stats);
    } else {
      found->second.Merge(stats);
    }
  }
  for (const auto& [name, stats] : other.images) images[name].Merge(stats);
}

nlohmann::json DatasetStats::ToJson() const {
  nlohmann::json json = nlohmann::json::object();
  for (const auto& [name, stats] : numeric) json[name] = StatsJson(stats.Compute(), false);
  for (const auto& [name, stats] : images) json[name] = StatsJson(stats.Compute(), true);
  return json;
}

DatasetStats EpisodeStats(const RecordedEpisode& episode, const DatasetLayout& layout, int64_t episode_index,
                          int64_t first_index) {
  DatasetStats stats;
  for (const VectorFeature& feature : VectorFeatures(layout)) {
    NumericStats values(feature.size);
    const std::vector<float>& rows = VectorOf(episode, feature.name);
    for (int64_t frame = 0; frame < episode.frames; ++frame)
      values.Add(&rows[static_cast<std::size_t>(frame * feature.size)]);
    stats.numeric.emplace(feature.name, std::move(values));
  }
  NumericStats timestamp(1), frame_index(1), episode_number(1), index(1), task_index(1);
  for (int64_t frame = 0; frame < episode.frames; ++frame) {
    // As stored: float32 timestamps.
    timestamp.Add(static_cast<double>(static_cast<float>(static_cast<double>(frame) / layout.fps)));
    frame_index.Add(static_cast<double>(frame));
    episode_number.Add(static_cast<double>(episode_index));
    index.Add(static_cast<double>(first_index + frame));
    task_index.Add(static_cast<double>(episode.task_index));
  }
  stats.numeric.emplace("timestamp", std::move(timestamp));
  stats.numeric.emplace("frame_index", std::move(frame_index));
  stats.numeric.emplace("episode_index", std::move(episode_number));
  stats.numeric.emplace("index", std::move(index));
  stats.numeric.emplace("task_index", std::move(task_index));
  for (std::size_t camera = 0; camera < layout.cameras.size(); ++camera) {
    stats.images[CameraVideoKey(layout.cameras[camera])] = episode.image_stats[camera];
  }
  return stats;
}

}  // namespace tavis::batch::dataset

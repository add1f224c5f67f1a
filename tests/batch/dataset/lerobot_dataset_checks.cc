#include "tests/batch/dataset/lerobot_dataset_checks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "tests/batch/dataset/pyav_video.h"

namespace tavis::batch::dataset::testing {
namespace {

const std::vector<std::string> kStats = {"min", "max", "mean", "std", "count", "q01", "q10", "q50", "q90", "q99"};

// The episode a global row belongs to, from the episodes' index ranges.
int64_t EpisodeOfRow(const DatasetView& view, int64_t row) {
  for (std::size_t e = 0; e < view.episodes.size(); ++e) {
    if (row >= view.episodes[e].from_index && row < view.episodes[e].to_index) return static_cast<int64_t>(e);
  }
  return -1;
}

}  // namespace

void ExpectDataRowsAsLeRobotReadsThem(const DatasetView& view) {
  ASSERT_EQ(view.hyparquet_rows.size(), view.duckdb_rows.size());
  ASSERT_EQ(static_cast<int64_t>(view.hyparquet_rows.size()), view.info["total_frames"].get<int64_t>());
  ASSERT_EQ(static_cast<int64_t>(view.episodes.size()), view.info["total_episodes"].get<int64_t>());
  std::set<std::string> expected_columns;
  for (const auto& [name, feature] : view.info["features"].items()) {
    if (feature["dtype"] != "video") expected_columns.insert(name);
  }
  int64_t next_from = 0;
  for (const EpisodeEntry& episode : view.episodes) {
    EXPECT_EQ(episode.from_index, next_from);
    EXPECT_EQ(episode.to_index - episode.from_index, episode.length);
    next_from = episode.to_index;
  }
  for (std::size_t i = 0; i < view.hyparquet_rows.size(); ++i) {
    const nlohmann::json& row = view.hyparquet_rows[i];
    EXPECT_EQ(row, view.duckdb_rows[i]) << "hyparquet and DuckDB differ on row " << i;
    std::set<std::string> columns;
    for (const auto& [name, value] : row.items()) {
      columns.insert(name);
      const nlohmann::json& shape = view.info["features"][name]["shape"];
      if (value.is_array()) {
        EXPECT_EQ(value.size(), shape[0].get<std::size_t>()) << name << " row " << i;
      } else {
        EXPECT_EQ(shape, nlohmann::json({1})) << name << " is a scalar column";
      }
    }
    ASSERT_EQ(columns, expected_columns) << "row " << i;
    const int64_t index = static_cast<int64_t>(i);
    ASSERT_EQ(Int(row["index"]), index) << "a gap or disorder in `index` in sorted-path order";
    const int64_t episode = EpisodeOfRow(view, index);
    ASSERT_GE(episode, 0) << "row " << i << " is in no episode's range";
    const EpisodeEntry& entry = view.episodes[static_cast<std::size_t>(episode)];
    const int64_t frame = index - entry.from_index;
    EXPECT_EQ(Int(row["episode_index"]), episode) << "row " << i;
    EXPECT_EQ(Int(row["frame_index"]), frame) << "row " << i;
    EXPECT_EQ(row["timestamp"].get<double>(),
              static_cast<double>(static_cast<float>(static_cast<double>(frame) / view.fps)))
        << "row " << i;
    const int64_t task = Int(row["task_index"]);
    ASSERT_TRUE(task >= 0 && task < static_cast<int64_t>(view.tasks.size())) << "row " << i;
    EXPECT_NE(std::find(entry.tasks.begin(), entry.tasks.end(), view.tasks[static_cast<std::size_t>(task)]),
              entry.tasks.end())
        << "row " << i << "'s task is not among its episode's tasks";
  }
}

void ExpectStatsJsonComplete(const DatasetView& view) {
  const int64_t frames = view.info["total_frames"];
  for (const auto& [name, feature] : view.info["features"].items()) {
    if (feature["dtype"] == "string") {
      EXPECT_FALSE(view.stats.contains(name)) << name;
      continue;
    }
    ASSERT_TRUE(view.stats.contains(name)) << name << " has no stats";
    const nlohmann::json& stats = view.stats[name];
    const bool video = feature["dtype"] == "video";
    for (const std::string& stat : kStats) {
      ASSERT_TRUE(stats.contains(stat)) << name << " lacks " << stat;
      if (stat == "count") {
        // Every frame is sampled: the episodes are shorter than LeRobot's 100-frame minimum.
        EXPECT_EQ(stats[stat], nlohmann::json({frames})) << name;
      } else if (video) {
        ASSERT_EQ(stats[stat].size(), 3u) << name << "/" << stat;
        for (const nlohmann::json& channel : stats[stat]) {
          ASSERT_TRUE(channel.is_array() && channel.size() == 1 && channel[0].size() == 1)
              << name << "/" << stat << " not 3x1x1";
          EXPECT_GE(channel[0][0].get<double>(), 0.0) << name << "/" << stat;
          EXPECT_LE(channel[0][0].get<double>(), 1.0) << name << "/" << stat;
        }
      } else {
        EXPECT_EQ(stats[stat].size(), feature["shape"][0].get<std::size_t>()) << name << "/" << stat;
      }
    }
  }
}

LookedUpFrames ExpectVideosAsLeRobotReadsThem(const DatasetView& view, const std::string& scratch_dir) {
  LookedUpFrames found;
  for (const std::string& key : view.video_keys) {
    const nlohmann::json& info = view.info["features"][key]["info"];
    // Episodes by file, in episode order.
    std::map<std::string, std::vector<int64_t>> files;
    for (std::size_t e = 0; e < view.episodes.size(); ++e)
      files[view.episodes[e].videos.at(key).path].push_back(static_cast<int64_t>(e));
    for (const auto& [path, episodes] : files) {
      std::vector<FrameQuery> queries;
      std::vector<std::pair<int64_t, int>> asked;
      std::vector<int64_t> starts;  // the first frame of each episode in the file
      int64_t frames = 0;
      double expected_from = 0;
      for (const int64_t e : episodes) {
        const EpisodeEntry& episode = view.episodes[static_cast<std::size_t>(e)];
        const VideoSpan& span = episode.videos.at(key);
        EXPECT_DOUBLE_EQ(span.from_timestamp, expected_from) << key << " episode " << e << " in " << path;
        EXPECT_NEAR(span.to_timestamp - span.from_timestamp, static_cast<double>(episode.length) / view.fps, 1e-9)
            << key << " episode " << e;
        EXPECT_EQ(std::lround(span.to_timestamp * view.fps) - std::lround(span.from_timestamp * view.fps),
                  episode.length)
            << "dataset_tools' check, " << key << " episode " << e;
        expected_from = span.to_timestamp;
        starts.push_back(frames);
        frames += episode.length;
        for (const int k : {0, static_cast<int>(episode.length / 2), static_cast<int>(episode.length - 1)}) {
          queries.push_back({span.from_timestamp, k});
          asked.emplace_back(e, k);
        }
      }
      const PyAvReport report = CheckVideoWithPyAv(path, view.fps, queries, scratch_dir);
      const nlohmann::json& stream = report.stream;
      EXPECT_EQ(stream["frame_count"], frames) << path;
      EXPECT_EQ(stream["average_rate"], std::to_string(view.fps)) << path;
      EXPECT_EQ(stream["pix_fmt"], "yuv420p") << path;
      EXPECT_EQ(stream["pix_fmt"], info["video.pix_fmt"]) << path;
      EXPECT_EQ(stream["width"], info["video.width"]) << path;
      EXPECT_EQ(stream["height"], info["video.height"]) << path;
      // LeRobot's to_timestamp is the probed stream duration.
      EXPECT_DOUBLE_EQ(stream["duration_s"].get<double>(),
                       view.episodes[static_cast<std::size_t>(episodes.back())].videos.at(key).to_timestamp)
          << path;
      const auto keyframes = stream["keyframes"].get<std::vector<bool>>();
      for (const int64_t start : starts) {
        EXPECT_TRUE(static_cast<std::size_t>(start) < keyframes.size() && keyframes[static_cast<std::size_t>(start)])
            << path << ": no keyframe at episode start, frame " << start;
      }
      for (std::size_t q = 0; q < queries.size(); ++q) {
        EXPECT_TRUE(report.frames[q].has_value()) << path << ": LeRobot's lookup finds no frame for episode "
                                                  << asked[q].first << " frame " << asked[q].second;
        if (report.frames[q]) found[{key, asked[q].first, asked[q].second}] = *report.frames[q];
      }
    }
  }
  return found;
}

}  // namespace tavis::batch::dataset::testing

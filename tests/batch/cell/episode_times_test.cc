#include "batch/cell/episode_times.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/support/thrown_message.h"

namespace tavis::batch::cell {
namespace {

EpisodeTimes Times(double span, double policy, double physics, double render, double video, double other) {
  EpisodeTimes times;
  times.span_s = span;
  times.parts = {policy, physics, render, video, other};
  return times;
}

TEST(EpisodeTimes, ALineNamesTheEpisodeItsSpanAndEveryPartAndReadsBack) {
  const std::string line = EpisodeTimesJsonLine(7, Times(2.5, 1.0, 0.5, 0.25, 0.125, 0.0625));
  EXPECT_EQ(nlohmann::json::parse(line), nlohmann::json::parse(R"({"episode": 7, "span_s": 2.5, "policy_s": 1.0,
      "physics_s": 0.5, "render_s": 0.25, "video_s": 0.125, "other_s": 0.0625})"));
  const EpisodeTimesLine parsed = ParseEpisodeTimesJsonLine(line);
  EXPECT_EQ(parsed.episode, 7);
  ASSERT_TRUE(parsed.times.has_value());
  EXPECT_EQ(parsed.times->span_s, 2.5);
  EXPECT_EQ(parsed.times->parts, Times(2.5, 1.0, 0.5, 0.25, 0.125, 0.0625).parts);
}

TEST(EpisodeTimes, AnEpisodeWithoutTimesHasTheSameKeysNull) {
  const std::string line = EpisodeTimesJsonLine(3, std::nullopt);
  EXPECT_EQ(nlohmann::json::parse(line), nlohmann::json::parse(R"({"episode": 3, "span_s": null, "policy_s": null,
      "physics_s": null, "render_s": null, "video_s": null, "other_s": null})"));
  const EpisodeTimesLine parsed = ParseEpisodeTimesJsonLine(line);
  EXPECT_EQ(parsed.episode, 3);
  EXPECT_FALSE(parsed.times.has_value());
}

TEST(EpisodeTimes, ABadValueIsNamed) {
  const std::string line =
      R"({"episode":0,"span_s":1,"policy_s":-1,"physics_s":0,"render_s":0,"video_s":0,"other_s":0})";
  EXPECT_EQ(testing::ThrownMessage<std::invalid_argument>([&] { ParseEpisodeTimesJsonLine(line); }),
            "policy_s -1 is not a number of seconds");
}

TEST(EpisodeTimes, TheSummaryGivesEachPartsTotalMedianAndNinetiethPercentile) {
  std::vector<EpisodeTimes> measured;
  for (int i = 1; i <= 10; ++i) measured.push_back(Times(i, 0.5 * i, 0.0, 0.0, i == 10 ? 1.0 : 0.0, 0.25));
  const nlohmann::json summary = EpisodeTimesSummaryJson(measured);
  EXPECT_EQ(summary.at("file"), "episode_times.jsonl");
  EXPECT_EQ(summary.at("measured"), 10);
  EXPECT_EQ(summary.at("span_s"), nlohmann::json({{"total_s", 55.0}, {"median_s", 5.5}, {"p90_s", 9.0}}));
  EXPECT_EQ(summary.at("policy_s"), nlohmann::json({{"total_s", 27.5}, {"median_s", 2.75}, {"p90_s", 4.5}}));
  EXPECT_EQ(summary.at("video_s"), nlohmann::json({{"total_s", 1.0}, {"median_s", 0.0}, {"p90_s", 0.0}}));
  EXPECT_EQ(summary.at("other_s").at("total_s"), 2.5);
  const nlohmann::json none = EpisodeTimesSummaryJson({});
  EXPECT_EQ(none.at("measured"), 0);
  EXPECT_TRUE(none.at("physics_s").is_null());
}

}  // namespace
}  // namespace tavis::batch::cell

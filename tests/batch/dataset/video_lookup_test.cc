// Our mp4 files as LeRobot reads them, checked by independent readers: Debian's PyAV 10
// (check_video.py replays LeRobot's seek-and-decode lookup) and ffprobe 5.1. Three episodes of
// odd and even lengths are laid back to back, as the v3.0 dataset writer stores them.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/dataset/video/video_writer.h"
#include "tests/batch/dataset/synthetic_frames.h"
#include "tests/support/child_process.h"

namespace tavis::batch::dataset {
namespace {

using testing::Psnr;
using testing::RgbFrame;

constexpr const char* kPyAvHint = "is python3-av (PyAV 10) installed for /usr/bin/python3?";
const std::vector<int> kEpisodeLengths = {7, 12, 5};
constexpr int kFps = 30;

struct LookupCase {
  video::VideoCodec codec;
  int width;
  int height;
};

std::string CaseName(const ::testing::TestParamInfo<LookupCase>& info) {
  return video::VideoCodecName(info.param.codec) + "_" + std::to_string(info.param.width) + "x" +
         std::to_string(info.param.height);
}

struct Query {
  int episode;
  int frame_index;  // within the episode
};

class VideoLookupTest : public ::testing::TestWithParam<LookupCase> {
 protected:
  void SetUp() override {
    dir_ = testing::ScratchDir();
    path_ = dir_ + "/video.mp4";
    video::VideoSettings settings;
    settings.codec = GetParam().codec;
    settings.width = GetParam().width;
    settings.height = GetParam().height;
    settings.fps = kFps;
    frames_ = testing::WriteEpisodes(path_, settings, kEpisodeLengths);
  }

  int EpisodeStart(int episode) const {
    int start = 0;
    for (int e = 0; e < episode; ++e) start += kEpisodeLengths[static_cast<std::size_t>(e)];
    return start;
  }

  // check_video.py's report; each query's frame lands in dir_/query_<i>.rgb.
  nlohmann::json Check(const std::vector<Query>& queries) const {
    std::vector<std::string> args = {path_, std::to_string(kFps)};
    for (std::size_t i = 0; i < queries.size(); ++i) {
      // from_timestamp: the previous episodes' total duration, as LeRobot accumulates it.
      args.push_back(std::to_string(static_cast<double>(EpisodeStart(queries[i].episode)) / kFps));
      args.push_back(std::to_string(queries[i].frame_index));
      args.push_back(QueryPath(i));
    }
    tavis::testing::ChildProcess script(
        tavis::testing::kDebianPython,
        tavis::testing::ScriptArgs(std::string(TAVIS_TEST_DATA_DIR) + "/check_video.py", args), kPyAvHint);
    return nlohmann::json::parse(script.ReadAllOutput(std::chrono::seconds(60)));
  }

  std::string QueryPath(std::size_t i) const { return dir_ + "/query_" + std::to_string(i) + ".rgb"; }

  std::string dir_;
  std::string path_;
  std::vector<RgbFrame> frames_;
};

TEST_P(VideoLookupTest, PyAvSeesConstantRateFramesAndKeyframedEpisodes) {
  const nlohmann::json report = Check({});
  const int total = EpisodeStart(3);
  EXPECT_EQ(report["pix_fmt"], "yuv420p");
  EXPECT_EQ(report["width"], GetParam().width);
  EXPECT_EQ(report["height"], GetParam().height);
  EXPECT_EQ(report["average_rate"], std::to_string(kFps));
  EXPECT_EQ(report["guessed_rate"], std::to_string(kFps));
  EXPECT_EQ(report["base_rate"], std::to_string(kFps));
  EXPECT_EQ(report["frame_count"], total);
  EXPECT_NEAR(report["duration_s"].get<double>(), static_cast<double>(total) / kFps, 1e-6);
  const auto frame_pts = report["frame_pts_s"].get<std::vector<double>>();
  ASSERT_EQ(frame_pts.size(), static_cast<std::size_t>(total));
  for (int k = 0; k < total; ++k)
    EXPECT_NEAR(frame_pts[static_cast<std::size_t>(k)], static_cast<double>(k) / kFps, 1e-6) << k;
  const auto keyframes = report["keyframes"].get<std::vector<bool>>();
  ASSERT_EQ(keyframes.size(), static_cast<std::size_t>(total));
  for (int episode = 0; episode < 3; ++episode) {
    EXPECT_TRUE(keyframes[static_cast<std::size_t>(EpisodeStart(episode))])
        << "episode " << episode << " starts on frame " << EpisodeStart(episode);
  }
  // gop 2: never more than one frame between keyframes.
  for (int k = 1; k < total; ++k) {
    EXPECT_TRUE(keyframes[static_cast<std::size_t>(k)] || keyframes[static_cast<std::size_t>(k - 1)]) << k;
  }
}

TEST_P(VideoLookupTest, LeRobotPyAvLookupReturnsTheEncodedFrame) {
  const std::vector<Query> queries = {{0, 0}, {0, 6}, {1, 0}, {1, 5}, {1, 11}, {2, 0}, {2, 3}, {2, 4}};
  const nlohmann::json report = Check(queries);
  ASSERT_EQ(report["lookups"].size(), queries.size());
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const nlohmann::json& lookup = report["lookups"][i];
    const std::string name =
        "episode " + std::to_string(queries[i].episode) + " frame " + std::to_string(queries[i].frame_index);
    ASSERT_TRUE(lookup["found"].get<bool>()) << name << ": no frame within 1e-4 s of " << lookup["query_s"];
    const RgbFrame decoded = testing::ReadBytes(QueryPath(i));
    const int k = EpisodeStart(queries[i].episode) + queries[i].frame_index;
    const RgbFrame& encoded = frames_[static_cast<std::size_t>(k)];
    EXPECT_GE(Psnr(decoded, encoded), 30.0) << name;
    // The test discriminates: a neighbouring frame scores far lower.
    const RgbFrame& neighbour = frames_[static_cast<std::size_t>(k == 0 ? 1 : k - 1)];
    EXPECT_LT(Psnr(decoded, neighbour), 25.0) << name;
  }
}

TEST_P(VideoLookupTest, FfprobeSeesTheCodecAndEqualRates) {
  tavis::testing::ChildProcess ffprobe(
      "/usr/bin/ffprobe",
      {"-v", "error", "-count_packets", "-select_streams", "v:0", "-show_entries",
       "stream=codec_name,pix_fmt,avg_frame_rate,r_frame_rate,nb_frames,nb_read_packets", "-of", "json", path_},
      "is Debian's ffmpeg installed?");
  const nlohmann::json stream = nlohmann::json::parse(ffprobe.ReadAllOutput(std::chrono::seconds(30)))["streams"][0];
  const std::string total = std::to_string(EpisodeStart(3));
  EXPECT_EQ(stream["codec_name"], video::VideoCodecName(GetParam().codec));
  EXPECT_EQ(stream["pix_fmt"], "yuv420p");
  EXPECT_EQ(stream["avg_frame_rate"], std::to_string(kFps) + "/1");
  EXPECT_EQ(stream["r_frame_rate"], std::to_string(kFps) + "/1");
  EXPECT_EQ(stream["nb_frames"], total);
  EXPECT_EQ(stream["nb_read_packets"], total);
}

INSTANTIATE_TEST_SUITE_P(Codecs, VideoLookupTest,
                         ::testing::Values(LookupCase{video::VideoCodec::kH264, 64, 48},
                                           LookupCase{video::VideoCodec::kAv1, 64, 64},
                                           LookupCase{video::VideoCodec::kH264, 224, 224},
                                           LookupCase{video::VideoCodec::kAv1, 224, 224}),
                         CaseName);

}  // namespace
}  // namespace tavis::batch::dataset

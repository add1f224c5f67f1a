// video::Mp4VideoWriter's own contract: settings checked up front, errors that name the file, the
// partial-file protocol, byte-identical output, and what video::ProbeVideo reads back.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <csignal>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <thread>

#include "batch/dataset/video/video_probe.h"
#include "batch/dataset/video/video_writer.h"
#include "tests/batch/dataset/synthetic_frames.h"

namespace tavis::batch::dataset {
namespace {

using testing::ReadBytes;
using testing::ScratchDir;
using testing::SyntheticFrame;
using testing::WriteEpisodes;

namespace fs = std::filesystem;

video::VideoSettings Small(video::VideoCodec codec) {
  video::VideoSettings settings;
  settings.codec = codec;
  settings.width = 64;
  settings.height = codec == video::VideoCodec::kAv1 ? 64 : 48;
  settings.fps = 30;
  return settings;
}

// The message of the exception `write` throws, or "" when it throws none.
template <typename Exception, typename Action>
std::string MessageOf(Action write) {
  try {
    write();
  } catch (const Exception& error) {
    return error.what();
  }
  return "";
}

class VideoWriterCodecTest : public ::testing::TestWithParam<video::VideoCodec> {};

TEST_P(VideoWriterCodecTest, SameFramesGiveByteIdenticalFiles) {
  const std::string dir = ScratchDir();
  const video::VideoSettings settings = Small(GetParam());
  WriteEpisodes(dir + "/first.mp4", settings, {7, 12, 5});
  // Two writers at once, as the dataset writer runs one per camera stream.
  std::thread parallel([&] { WriteEpisodes(dir + "/parallel.mp4", settings, {7, 12, 5}); });
  WriteEpisodes(dir + "/second.mp4", settings, {7, 12, 5});
  parallel.join();
  const auto first = ReadBytes(dir + "/first.mp4");
  ASSERT_GT(first.size(), 1000U);
  EXPECT_TRUE(first == ReadBytes(dir + "/second.mp4"));
  EXPECT_TRUE(first == ReadBytes(dir + "/parallel.mp4"));
}

TEST_P(VideoWriterCodecTest, ProbeReadsBackCodecSizeRateFramesAndDuration) {
  const std::string dir = ScratchDir();
  video::VideoSettings settings = Small(GetParam());
  settings.fps = 60;
  WriteEpisodes(dir + "/video.mp4", settings, {7, 12, 5});
  const video::VideoProbe probe = video::ProbeVideo(dir + "/video.mp4");
  EXPECT_EQ(probe.codec, video::VideoCodecName(settings.codec));
  EXPECT_EQ(probe.pix_fmt, "yuv420p");
  EXPECT_EQ(probe.width, settings.width);
  EXPECT_EQ(probe.height, settings.height);
  EXPECT_EQ(probe.fps_num, 60);
  EXPECT_EQ(probe.fps_den, 1);
  EXPECT_EQ(probe.frame_count, 24);
  EXPECT_NEAR(probe.duration_s, 24.0 / 60.0, 1e-9);
}

TEST_P(VideoWriterCodecTest, BytesWrittenGrowsAndIsTheFileSizeAfterClose) {
  const std::string dir = ScratchDir();
  const video::VideoSettings settings = Small(GetParam());
  video::Mp4VideoWriter writer(dir + "/video.mp4", settings);
  const std::int64_t header = writer.bytes_written();
  // Encoders hold frames in their lookahead before the first packet (libsvtav1 keeps more on some
  // machines than on others): write until bytes appear, well before the end of a long episode.
  int frames = 0;
  while (writer.bytes_written() == header && frames < 600) {
    const auto frame = SyntheticFrame(settings.width, settings.height, 0, frames);
    writer.WriteFrame(frame.data(), frame.size());
    ++frames;
  }
  EXPECT_EQ(writer.frames_written(), frames);
  EXPECT_GT(writer.bytes_written(), header) << "no bytes after " << frames << " frames";
  writer.Close();
  EXPECT_EQ(writer.bytes_written(), static_cast<std::int64_t>(fs::file_size(dir + "/video.mp4")));
}

std::string CodecName(const ::testing::TestParamInfo<video::VideoCodec>& test) {
  return video::VideoCodecName(test.param);
}

INSTANTIATE_TEST_SUITE_P(Codecs, VideoWriterCodecTest,
                         ::testing::Values(video::VideoCodec::kH264, video::VideoCodec::kAv1), CodecName);

TEST(VideoWriter, CloseRenamesThePartialFile) {
  const std::string dir = ScratchDir();
  video::Mp4VideoWriter writer(dir + "/video.mp4", Small(video::VideoCodec::kH264));
  EXPECT_TRUE(fs::exists(dir + "/video.mp4.partial"));
  EXPECT_FALSE(fs::exists(dir + "/video.mp4"));
  const auto frame = SyntheticFrame(64, 48, 0, 0);
  writer.WriteFrame(frame.data(), frame.size());
  writer.Close();
  writer.Close();
  EXPECT_TRUE(fs::exists(dir + "/video.mp4"));
  EXPECT_FALSE(fs::exists(dir + "/video.mp4.partial"));
}

TEST(VideoWriter, WriterDestroyedWithoutCloseLeavesNoFile) {
  const std::string dir = ScratchDir();
  {
    video::Mp4VideoWriter writer(dir + "/video.mp4", Small(video::VideoCodec::kH264));
    for (int index = 0; index < 5; ++index) {
      const auto frame = SyntheticFrame(64, 48, 0, index);
      writer.WriteFrame(frame.data(), frame.size());
    }
  }
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(VideoWriter, OddDimensionsAreRejectedBeforeAnyFileIsCreated) {
  const std::string dir = ScratchDir();
  video::VideoSettings settings = Small(video::VideoCodec::kH264);
  settings.width = 63;
  const std::string message =
      MessageOf<std::invalid_argument>([&] { video::Mp4VideoWriter(dir + "/odd.mp4", settings); });
  EXPECT_NE(message.find(dir + "/odd.mp4"), std::string::npos) << message;
  EXPECT_NE(message.find("width 63 is odd"), std::string::npos) << message;
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(VideoWriter, Av1FramesBelowTheSvtMinimumAreRejected) {
  video::VideoSettings settings = Small(video::VideoCodec::kAv1);
  settings.height = 48;
  const std::string message =
      MessageOf<std::invalid_argument>([&] { video::Mp4VideoWriter(ScratchDir() + "/a.mp4", settings); });
  EXPECT_NE(message.find("64x48 are too small"), std::string::npos) << message;
}

TEST(VideoWriter, UnknownCodecNameIsNamed) {
  const std::string message = MessageOf<std::invalid_argument>([] { video::ParseVideoCodec("hevc"); });
  EXPECT_NE(message.find("\"hevc\""), std::string::npos) << message;
  EXPECT_EQ(video::ParseVideoCodec("libsvtav1"), video::VideoCodec::kAv1);
}

TEST(VideoWriter, UnwritablePathNamesTheFileAndTheReason) {
  const std::string path = ScratchDir() + "/missing_folder/video.mp4";
  const std::string message =
      MessageOf<std::runtime_error>([&] { video::Mp4VideoWriter(path, Small(video::VideoCodec::kH264)); });
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find("No such file or directory"), std::string::npos) << message;
}

TEST(VideoWriter, WrongFrameSizeNamesBothSizes) {
  video::Mp4VideoWriter writer(ScratchDir() + "/video.mp4", Small(video::VideoCodec::kH264));
  const auto frame = SyntheticFrame(64, 46, 0, 0);
  const std::string message = MessageOf<std::runtime_error>([&] { writer.WriteFrame(frame.data(), frame.size()); });
  EXPECT_NE(message.find("frame of 8832 bytes, expected 64x48x3 = 9216"), std::string::npos) << message;
}

// A full disk, simulated with a file size limit: writes past it fail (EFBIG) as they would
// with ENOSPC, through the same error path.
TEST(VideoWriter, WriteFailureNamesTheFile) {
  const std::string path = ScratchDir() + "/video.mp4";
  rlimit original{};
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &original), 0);
  const auto previous_handler = std::signal(SIGXFSZ, SIG_IGN);
  rlimit limited = original;
  limited.rlim_cur = 64 * 1024;
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &limited), 0);
  const std::string message = MessageOf<std::runtime_error>([&] {
    video::Mp4VideoWriter writer(path, Small(video::VideoCodec::kH264));
    for (int index = 0; index < 2000; ++index) {
      const auto frame = SyntheticFrame(64, 48, index, index);
      writer.WriteFrame(frame.data(), frame.size());
    }
    writer.Close();
  });
  setrlimit(RLIMIT_FSIZE, &original);
  std::signal(SIGXFSZ, previous_handler);
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find("File too large"), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".partial"));
}

TEST(VideoWriter, AppendsEpisodesEncodedApartAndRefusesOneOfAnotherSize) {
  const std::string dir = testing::ScratchDir();
  video::Mp4VideoWriter writer(dir + "/video.mp4", Small(video::VideoCodec::kH264));
  for (int episode = 0; episode < 2; ++episode) {
    video::EpisodeEncoder encoder(Small(video::VideoCodec::kH264), "camera");
    for (int index = 0; index < 5 + episode; ++index) {
      const auto frame = testing::SyntheticFrame(64, 48, episode, index);
      encoder.WriteFrame(frame.data(), frame.size());
    }
    const video::EncodedEpisode encoded = encoder.Finish();
    EXPECT_EQ(encoded.frames, 5 + episode);
    EXPECT_TRUE(encoded.packets.front().key) << "each episode starts on a keyframe";
    writer.AppendEpisode(encoded);
  }
  video::VideoSettings larger = Small(video::VideoCodec::kH264);
  larger.width = 96;
  video::EpisodeEncoder other(larger, "camera");
  const auto frame = testing::SyntheticFrame(96, 48, 0, 0);
  other.WriteFrame(frame.data(), frame.size());
  try {
    writer.AppendEpisode(other.Finish());
    ADD_FAILURE() << "an episode of another size was appended";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("96x48 frames in a 64x48 file"), std::string::npos) << error.what();
  }
  writer.Close();
  const video::VideoProbe probe = video::ProbeVideo(dir + "/video.mp4");
  EXPECT_EQ(probe.frame_count, 11);
  EXPECT_NEAR(probe.duration_s, 11.0 / Small(video::VideoCodec::kH264).fps, 1e-9);
}

}  // namespace
}  // namespace tavis::batch::dataset

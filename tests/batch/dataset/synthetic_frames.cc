#include "tests/batch/dataset/synthetic_frames.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>

#include "batch/dataset/video/video_writer.h"

namespace tavis::batch::dataset::testing {
namespace {

constexpr double kTwoPi = 6.283185307179586;

double Wave(double phase) { return std::sin(kTwoPi * phase); }

std::uint8_t Channel(double value) { return static_cast<std::uint8_t>(std::lround(std::clamp(value, 0.0, 255.0))); }

}  // namespace

RgbFrame SyntheticFrame(int width, int height, int episode, int index) {
  RgbFrame frame(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);
  const int square = std::max(6, width / 8);
  const int square_x = (index * 5 + episode * 17) % (width - square);
  const int square_y = (index * 3 + episode * 11) % (height - square);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const double u = static_cast<double>(x) / width;
      const double v = static_cast<double>(y) / height;
      std::uint8_t* pixel =
          &frame[(static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 3];
      const bool in_square = x >= square_x && x < square_x + square && y >= square_y && y < square_y + square;
      // Mostly brightness with a gentle tint: yuv420p keeps chroma at half resolution, so
      // strong colour detail would cost PSNR at these tiny sizes whatever the encoder does.
      const double luma = in_square ? 235.0
                                    : 128.0 + 60.0 * Wave(u + 0.07 * index + 0.3 * episode) +
                                          40.0 * Wave(1.5 * v - 0.05 * index + 0.2 * episode);
      const double tint = 20.0 * Wave(0.5 * (u + v) + 0.11 * index - 0.25 * episode);
      pixel[0] = Channel(luma + tint);
      pixel[1] = Channel(luma - 0.5 * tint);
      pixel[2] = Channel(luma - tint);
    }
  }
  return frame;
}

double Psnr(const RgbFrame& a, const RgbFrame& b) {
  if (a.size() != b.size() || a.empty()) return 0;
  double squared_error = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double difference = static_cast<double>(a[i]) - static_cast<double>(b[i]);
    squared_error += difference * difference;
  }
  if (squared_error == 0) return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(255.0 * 255.0 * static_cast<double>(a.size()) / squared_error);
}

std::vector<RgbFrame> WriteEpisodes(const std::string& path, const video::VideoSettings& settings,
                                    const std::vector<int>& episode_lengths) {
  video::Mp4VideoWriter writer(path, settings);
  std::vector<RgbFrame> frames;
  for (std::size_t episode = 0; episode < episode_lengths.size(); ++episode) {
    writer.BeginEpisode();
    for (int index = 0; index < episode_lengths[episode]; ++index) {
      frames.push_back(SyntheticFrame(settings.width, settings.height, static_cast<int>(episode), index));
      writer.WriteFrame(frames.back().data(), frames.back().size());
    }
  }
  writer.Close();
  return frames;
}

std::string ScratchDir() {
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = std::string(test->test_suite_name()) + "." + test->name();
  for (char& c : name) {
    if (c == '/') c = '_';
  }
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "tavis_video" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

std::vector<std::uint8_t> ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace tavis::batch::dataset::testing

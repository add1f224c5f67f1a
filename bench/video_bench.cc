// parquet::Encoding throughput of one camera stream (frames/s, items_per_second, wall time: SVT-AV1
// works in its own threads) with the encoder pinned as in the dataset writer, as the
// dataset writer runs it: 60 fps, episodes of 360 frames (36k frames per stream over 100
// episodes). Budget: 4 streams of 640x480 in well under 30 minutes on 2 cores next to the
// simulation and rendering. The frames are a rendered-like scene: a lit floor gradient, moving
// boxes and a little sensor noise.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "batch/dataset/video/video_writer.h"

namespace tavis::batch::dataset {
namespace {

constexpr int kFps = 60;
constexpr int kEpisodeLength = 360;
constexpr int kDistinctFrames = 120;

std::vector<std::vector<std::uint8_t>> SceneFrames(int width, int height) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> noise(-3, 3);
  std::vector<std::vector<std::uint8_t>> frames;
  for (int t = 0; t < kDistinctFrames; ++t) {
    std::vector<std::uint8_t> frame(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);
    const int box_x = width / 4 + t * width / (2 * kDistinctFrames);
    const int box_y = height / 2 - t * height / (4 * kDistinctFrames);
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const bool box = x >= box_x && x < box_x + width / 8 && y >= box_y && y < box_y + height / 8;
        const int shade = 60 + 120 * y / height + noise(rng);
        std::uint8_t* pixel =
            &frame[(static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 3];
        pixel[0] = static_cast<std::uint8_t>(box ? 200 : shade);
        pixel[1] = static_cast<std::uint8_t>(box ? 40 : shade - 10);
        pixel[2] = static_cast<std::uint8_t>(box ? 50 : shade - 30);
      }
    }
    frames.push_back(std::move(frame));
  }
  return frames;
}

void BM_EncodeStream(benchmark::State& state, video::VideoCodec codec) {
  video::VideoSettings settings;
  settings.codec = codec;
  settings.width = static_cast<int>(state.range(0));
  settings.height = static_cast<int>(state.range(1));
  settings.fps = kFps;
  const auto frames = SceneFrames(settings.width, settings.height);
  const std::string path = "/tmp/tavis_video_bench_" + video::VideoCodecName(codec) + ".mp4";
  video::Mp4VideoWriter writer(path, settings);
  std::int64_t frame = 0;
  for (auto _ : state) {
    if (frame % kEpisodeLength == 0) writer.BeginEpisode();
    const auto& rgb = frames[static_cast<std::size_t>(frame % kDistinctFrames)];
    writer.WriteFrame(rgb.data(), rgb.size());
    ++frame;
  }
  writer.Close();
  state.SetItemsProcessed(frame);
  state.counters["bytes_per_frame"] = static_cast<double>(writer.bytes_written()) / static_cast<double>(frame);
  std::remove(path.c_str());
}

BENCHMARK_CAPTURE(BM_EncodeStream, h264, video::VideoCodec::kH264)
    ->Args({640, 480})
    ->Args({224, 224})
    ->MinTime(3.0)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EncodeStream, av1, video::VideoCodec::kAv1)
    ->Args({640, 480})
    ->Args({224, 224})
    ->MinTime(3.0)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace tavis::batch::dataset

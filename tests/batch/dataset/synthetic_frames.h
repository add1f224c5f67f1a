// Test support for the video tests: synthetic RGB24 frames that differ per frame and per
// episode (smooth moving waves and a moving square, so a wrong frame scores a low PSNR), PSNR,
// and scratch files.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "batch/dataset/video/video_settings.h"

namespace tavis::batch::dataset::testing {

using RgbFrame = std::vector<std::uint8_t>;

// Frame `index` of episode `episode`, width x height x 3, row-major.
RgbFrame SyntheticFrame(int width, int height, int episode, int index);

// Peak signal-to-noise ratio in dB of two frames of the same size (infinity when identical).
double Psnr(const RgbFrame& a, const RgbFrame& b);

// Encodes episodes of the given lengths into `path` (BeginEpisode before each) and returns
// every frame written, in file order.
std::vector<RgbFrame> WriteEpisodes(const std::string& path, const video::VideoSettings& settings,
                                    const std::vector<int>& episode_lengths);

// A fresh empty folder under the test temp dir, named after the running test.
std::string ScratchDir();

std::vector<std::uint8_t> ReadBytes(const std::string& path);

}  // namespace tavis::batch::dataset::testing

#include "batch/rollout/video_frame.h"

#include <cstdint>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace tavis::batch::rollout {
namespace {

std::vector<uint8_t> Solid(int width, int height, uint8_t r, uint8_t g, uint8_t b) {
  std::vector<uint8_t> pixels(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);
  for (std::size_t i = 0; i < pixels.size(); i += 3) {
    pixels[i] = r;
    pixels[i + 1] = g;
    pixels[i + 2] = b;
  }
  return pixels;
}

const uint8_t* Pixel(const render::RgbImage& image, int x, int y) {
  return image.pixels.data() +
         (static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) + static_cast<std::size_t>(x)) * 3;
}

TEST(VideoFrame, TilesTheCamerasUnderTheCaptionAtTheAnnouncedEvenSize) {
  const std::vector<uint8_t> red = Solid(160, 120, 200, 0, 0);
  const std::vector<uint8_t> blue = Solid(160, 120, 0, 0, 200);
  const std::vector<uint8_t> green = Solid(160, 120, 0, 200, 0);
  const render::RgbImage frame = ComposeVideoFrame(
      {{"head", 120, 160, red.data()}, {"left_wrist", 120, 160, blue.data()}, {"fixed", 120, 160, green.data()}},
      {"episode 3   step 7   0.35 s", "success"});
  const auto [width, height] = VideoFrameSize(3, 160, 120);
  EXPECT_EQ(frame.width, width);
  EXPECT_EQ(frame.height, height);
  EXPECT_EQ(frame.width % 2, 0);
  EXPECT_EQ(frame.height % 2, 0);
  // Two columns (a near-square grid of three), two rows, a caption band on top.
  EXPECT_GE(frame.width, 2 * 160);
  EXPECT_GE(frame.height, 2 * 120 + 20);
  // Each tile's far corner (away from its label) keeps the camera's colour: red top left, blue
  // top right, green bottom left; the empty fourth place stays dark.
  const int band = frame.height - (2 * 120 + 3 * 4);
  const uint8_t* top_left = Pixel(frame, 4 + 150, band + 4 + 110);
  EXPECT_EQ(top_left[0], 200);
  EXPECT_EQ(top_left[2], 0);
  const uint8_t* top_right = Pixel(frame, 8 + 160 + 150, band + 4 + 110);
  EXPECT_EQ(top_right[2], 200);
  EXPECT_EQ(top_right[0], 0);
  const uint8_t* bottom_left = Pixel(frame, 4 + 150, band + 8 + 120 + 110);
  EXPECT_EQ(bottom_left[1], 200);
  const uint8_t* empty = Pixel(frame, 8 + 160 + 80, band + 8 + 120 + 60);
  EXPECT_LT(empty[0] + empty[1] + empty[2], 3 * 40);
  // The caption is drawn in white on the band: some band pixels are bright.
  int bright = 0;
  for (int y = 0; y < band; ++y) {
    for (int x = 0; x < frame.width; ++x) bright += Pixel(frame, x, y)[0] > 200 ? 1 : 0;
  }
  EXPECT_GT(bright, 50);
}

TEST(VideoFrame, EveryCaptionGivesTheSameSize) {
  const std::vector<uint8_t> grey = Solid(64, 48, 90, 90, 90);
  const render::RgbImage none = ComposeVideoFrame({{"head", 48, 64, grey.data()}}, {});
  const render::RgbImage two =
      ComposeVideoFrame({{"head", 48, 64, grey.data()}}, {"a long first line of text", "second"});
  EXPECT_EQ(none.width, two.width);
  EXPECT_EQ(none.height, two.height);
  EXPECT_THROW(ComposeVideoFrame({{"head", 48, 64, grey.data()}}, {"1", "2", "3"}), std::invalid_argument);
}

}  // namespace
}  // namespace tavis::batch::rollout

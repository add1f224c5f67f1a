// The canvas's PNG: colours land in the right channels (read back by ReadPng, through libpng).
#include "batch/report/svg_canvas.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "render/image_io.h"

namespace tavis::batch::report {
namespace {

TEST(SvgCanvas, ThePngHasTheColoursAsRgb) {
  Canvas canvas(40, 30);
  canvas.Rect(0, 0, 20, 30, "#ff8000", 1.0, "");   // orange on the left half
  canvas.Rect(20, 0, 20, 30, "#0040c0", 1.0, "");  // blue on the right half
  const std::string path = ::testing::TempDir() + "tavis_svg_canvas.png";
  std::ofstream(path, std::ios::binary) << canvas.Png();
  const render::RgbImage image = render::ReadPng(path);
  ASSERT_EQ(image.width, 40);
  ASSERT_EQ(image.height, 30);
  auto pixel = [&](int x, int y, int channel) {
    return static_cast<int>(image.pixels[static_cast<std::size_t>(3 * (y * image.width + x) + channel)]);
  };
  EXPECT_EQ(pixel(10, 15, 0), 0xff);
  EXPECT_EQ(pixel(10, 15, 1), 0x80);
  EXPECT_EQ(pixel(10, 15, 2), 0x00);
  EXPECT_EQ(pixel(30, 15, 0), 0x00);
  EXPECT_EQ(pixel(30, 15, 1), 0x40);
  EXPECT_EQ(pixel(30, 15, 2), 0xc0);
}

}  // namespace
}  // namespace tavis::batch::report

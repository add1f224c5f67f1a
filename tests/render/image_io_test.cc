// PNG writing/reading and contact sheets.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/image_io.h"
#include "tests/support/child_process.h"

namespace tavis::render {
namespace {

std::vector<uint8_t> Gradient(int height, int width) {
  std::vector<uint8_t> rgb(static_cast<std::size_t>(height * width * 3));
  for (int i = 0; i < height * width; ++i) {
    rgb[3 * i] = static_cast<uint8_t>(i % 251);
    rgb[3 * i + 1] = static_cast<uint8_t>((i / width) * 2);
    rgb[3 * i + 2] = 200;
  }
  return rgb;
}

TEST(ImageIoTest, PngRoundTripKeepsRgbOrder) {
  const std::vector<uint8_t> rgb = Gradient(30, 40);
  const std::string path = ::testing::TempDir() + "tavis_render_roundtrip.png";
  WritePng(path, 30, 40, rgb.data());
  const RgbImage read = ReadPng(path);
  ASSERT_EQ(read.height, 30);
  ASSERT_EQ(read.width, 40);
  EXPECT_EQ(read.pixels, rgb);
}

std::string FileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Another reader (FFmpeg's PNG decoder through PyAV) sees the pixels WritePng was given, and
// EncodePng makes the very bytes WritePng writes.
TEST(ImageIoTest, AnIndependentDecoderReadsTheWrittenPixels) {
  const int height = 37;
  const int width = 53;  // odd sizes: rows are not padded
  const std::vector<uint8_t> rgb = Gradient(height, width);
  const std::string path = ::testing::TempDir() + "tavis_render_pyav.png";
  const std::string decoded = ::testing::TempDir() + "tavis_render_pyav.rgb";
  WritePng(path, height, width, rgb.data());
  EXPECT_EQ(EncodePng(height, width, rgb.data()), FileBytes(path));

  tavis::testing::ChildProcess reader(
      tavis::testing::kDebianPython,
      tavis::testing::ScriptArgs(std::string(TAVIS_TEST_DATA_DIR) + "/decode_png.py", {path, decoded}),
      "is python3-av (PyAV) installed for /usr/bin/python3?");
  const nlohmann::json seen = nlohmann::json::parse(reader.ReadAllOutput(std::chrono::seconds(60)));
  EXPECT_EQ(seen["width"], width);
  EXPECT_EQ(seen["height"], height);
  EXPECT_EQ(seen["format"], "rgb24");  // 8-bit RGB, no alpha, no palette
  const std::string pixels = FileBytes(decoded);
  EXPECT_EQ(std::vector<uint8_t>(pixels.begin(), pixels.end()), rgb);
}

TEST(ImageIoTest, ReadingSomethingElseNamesThePathAndTheReason) {
  const std::string path = ::testing::TempDir() + "tavis_render_not_a.png";
  std::ofstream(path) << "not a PNG";
  try {
    ReadPng(path);
    ADD_FAILURE() << "expected std::runtime_error";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("PNG"), std::string::npos) << error.what();
  }
  EXPECT_THROW(EncodePng(4, 0, Gradient(4, 4).data()), std::invalid_argument);
}

TEST(ImageIoTest, WriteFailureNamesThePath) {
  const std::vector<uint8_t> rgb = Gradient(4, 4);
  const std::string path = "/nonexistent-directory/for/tavis/image.png";
  try {
    WritePng(path, 4, 4, rgb.data());
    ADD_FAILURE() << "expected std::runtime_error";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("No such file or directory"), std::string::npos) << error.what();
  }
  EXPECT_THROW(WritePng(::testing::TempDir() + "x.png", 0, 4, rgb.data()), std::invalid_argument);
  EXPECT_THROW(ReadPng("/nonexistent-directory/missing.png"), std::runtime_error);
}

TEST(ImageIoTest, ContactSheetTilesFourLabelledViews) {
  const int height = 48;
  const int width = 64;
  std::vector<std::vector<uint8_t>> views;
  for (int v = 0; v < 4; ++v)
    views.emplace_back(static_cast<std::size_t>(height * width * 3), static_cast<uint8_t>(50 * (v + 1)));
  const std::vector<std::string> labels = {"head", "fixed", "left_wrist", "right_wrist"};
  std::vector<LabelledImage> images;
  for (int v = 0; v < 4; ++v) images.push_back({labels[v], height, width, views[v].data()});
  const RgbImage sheet = MakeContactSheet(images);

  constexpr int kMargin = 4;
  EXPECT_EQ(sheet.width, 2 * width + 3 * kMargin);
  EXPECT_EQ(sheet.height, 2 * height + 3 * kMargin);
  auto pixel = [&](int x, int y) { return sheet.pixels[static_cast<std::size_t>(3 * (y * sheet.width + x))]; };
  for (int v = 0; v < 4; ++v) {
    const int x0 = kMargin + (v % 2) * (width + kMargin);
    const int y0 = kMargin + (v / 2) * (height + kMargin);
    EXPECT_EQ(pixel(x0 + width - 2, y0 + height - 2), 50 * (v + 1)) << labels[v];  // the image itself
    int label_pixels = 0;                                                          // its top-left label
    for (int y = y0; y < y0 + 12; ++y) {
      for (int x = x0; x < x0 + 30; ++x) label_pixels += pixel(x, y) != 50 * (v + 1) ? 1 : 0;
    }
    EXPECT_GT(label_pixels, 100) << labels[v];
  }
  EXPECT_THROW(MakeContactSheet({}), std::invalid_argument);
}

}  // namespace
}  // namespace tavis::render

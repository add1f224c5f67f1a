// Golden images of a fixed scene, one per camera. Tolerance: mean absolute channel difference
// below 1.0 and fewer than 0.5 % of pixels with a channel differing by more than 16 (room for
// compiler and Embree-version rounding, none for a changed camera, light or colour).
// TAVIS_UPDATE_GOLDEN=1 rewrites the PNGs and skips the comparison, saying so.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

#include "render/image_io.h"
#include "tests/render/test_scenes.h"

namespace tavis::render {
namespace {

constexpr int kGoldenWidth = 320;
constexpr int kGoldenHeight = 240;
constexpr double kMaxMeanAbsDiff = 1.0;
constexpr double kMaxFractionOver16 = 0.005;

bool UpdateRequested() {
  const char* flag = std::getenv("TAVIS_UPDATE_GOLDEN");
  return flag != nullptr && std::strcmp(flag, "1") == 0;
}

class GoldenImageTest : public ::testing::TestWithParam<int> {};

TEST_P(GoldenImageTest, MatchesStoredPng) {
  const int camera = GetParam();
  testing::TestScene scene = testing::GoldenScene(kGoldenWidth, kGoldenHeight);
  BatchRenderer renderer(scene.layout, 1);
  ImageBatch images = renderer.MakeImageBatch();
  renderer.Render(scene.Inputs(), &images);
  const std::string name = scene.layout.cameras[static_cast<std::size_t>(camera)].name;
  const std::string path = testing::GoldenDirectory() + "/" + name + ".png";

  if (UpdateRequested()) {
    std::filesystem::create_directories(testing::GoldenDirectory());
    WritePng(path, kGoldenHeight, kGoldenWidth, images.rgb(0, camera));
    GTEST_SKIP() << "TAVIS_UPDATE_GOLDEN=1: regenerated " << path << " (not compared)";
  }
  ASSERT_TRUE(std::filesystem::exists(path)) << path << " is missing; run with TAVIS_UPDATE_GOLDEN=1 to create it";
  const RgbImage golden = ReadPng(path);
  ASSERT_EQ(golden.height, kGoldenHeight);
  ASSERT_EQ(golden.width, kGoldenWidth);

  const uint8_t* rendered = images.rgb(0, camera);
  double abs_diff_sum = 0.0;
  int pixels_over_16 = 0;
  const int pixels = kGoldenWidth * kGoldenHeight;
  for (int i = 0; i < pixels; ++i) {
    int largest = 0;
    for (int channel = 0; channel < 3; ++channel) {
      const int diff =
          std::abs(int{rendered[3 * i + channel]} - int{golden.pixels[static_cast<std::size_t>(3 * i + channel)]});
      abs_diff_sum += diff;
      largest = std::max(largest, diff);
    }
    pixels_over_16 += largest > 16 ? 1 : 0;
  }
  const double mean_abs_diff = abs_diff_sum / (3.0 * pixels);
  const double fraction_over_16 = static_cast<double>(pixels_over_16) / pixels;
  EXPECT_LT(mean_abs_diff, kMaxMeanAbsDiff) << name;
  EXPECT_LT(fraction_over_16, kMaxFractionOver16) << name;
}

std::string CameraName(const ::testing::TestParamInfo<int>& camera) {
  return testing::GoldenScene(1, 1).layout.cameras[static_cast<std::size_t>(camera.param)].name;
}

INSTANTIATE_TEST_SUITE_P(AllCameras, GoldenImageTest, ::testing::Values(0, 1, 2, 3), CameraName);

}  // namespace
}  // namespace tavis::render

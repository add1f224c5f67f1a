// Images whose sizes are not multiples of the tile (16) or packet block (4 x 4 or 4 x 2): the
// partial tiles and blocks at the right and bottom edges must shade every pixel once and trace
// exactly one primary ray per pixel.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <utility>

#include "tests/render/test_scenes.h"

namespace tavis::render {
namespace {

// A colour no pixel of the golden scene can take: it must be gone everywhere after rendering.
constexpr uint8_t kSentinel[3] = {251, 3, 249};

TEST(TileEdgesTest, OddSizedImagesAreShadedEverywhereWithOnePrimaryRayPerPixel) {
  for (const auto& [width, height] : {std::pair{37, 29}, std::pair{17, 5}, std::pair{3, 2}}) {
    testing::TestScene scene = testing::GoldenScene(width, height);
    RenderOptions options;
    options.with_depth = true;
    BatchRenderer renderer(scene.layout, 1, options);
    ImageBatch images = renderer.MakeImageBatch();
    for (int c = 0; c < images.n_cameras(); ++c) {
      for (int i = 0; i < width * height; ++i) std::copy(kSentinel, kSentinel + 3, images.rgb(0, c) + 3 * i);
    }
    const RenderStats stats = renderer.Render(scene.Inputs(), &images);

    int64_t hits = 0;
    for (int c = 0; c < images.n_cameras(); ++c) {
      for (int i = 0; i < width * height; ++i) {
        const uint8_t* rgb = images.rgb(0, c) + 3 * i;
        EXPECT_FALSE(rgb[0] == kSentinel[0] && rgb[1] == kSentinel[1] && rgb[2] == kSentinel[2])
            << width << "x" << height << " camera " << c << " pixel " << i << " was not shaded";
        hits += images.depth(0, c)[i] > 0.0f ? 1 : 0;
      }
    }
    const int64_t pixels = static_cast<int64_t>(images.n_cameras()) * width * height;
    EXPECT_EQ(stats.primary_rays, pixels) << width << "x" << height;
    EXPECT_EQ(stats.primary_hits, hits) << width << "x" << height;
    EXPECT_LE(stats.shadow_rays, stats.primary_hits) << width << "x" << height;
  }
}

}  // namespace
}  // namespace tavis::render

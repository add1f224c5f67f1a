#include "batch/dataset/feature_stats.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace tavis::batch::dataset {
namespace {

TEST(NumericStats, MatchNumpysPopulationStdAndLinearQuantiles) {
  NumericStats stats(2);
  const float rows[4][2] = {{4, -1}, {1, -1}, {3, -1}, {2, -1}};
  for (const auto& row : rows) stats.Add(row);
  const FeatureStats result = stats.Compute();
  EXPECT_EQ(result.count, 4);
  EXPECT_EQ(result.min, (std::vector<double>{1, -1}));
  EXPECT_EQ(result.max, (std::vector<double>{4, -1}));
  EXPECT_DOUBLE_EQ(result.mean[0], 2.5);
  EXPECT_DOUBLE_EQ(result.std[0], std::sqrt(1.25));  // numpy.std([1, 2, 3, 4])
  EXPECT_DOUBLE_EQ(result.std[1], 0.0);
  EXPECT_DOUBLE_EQ(result.q01[0], 1.03);  // numpy.quantile([1, 2, 3, 4], 0.01)
  EXPECT_DOUBLE_EQ(result.q10[0], 1.3);
  EXPECT_DOUBLE_EQ(result.q50[0], 2.5);
  EXPECT_DOUBLE_EQ(result.q90[0], 3.7);
  EXPECT_DOUBLE_EQ(result.q99[0], 3.97);
}

TEST(NumericStats, MergingEpisodesEqualsOneFeatureOverAllRows) {
  NumericStats first(1), second(1), all(1);
  for (double v : {0.5, 7.0, -2.0}) {
    first.Add(v);
    all.Add(v);
  }
  for (double v : {3.0, 3.5}) {
    second.Add(v);
    all.Add(v);
  }
  first.Merge(second);
  const FeatureStats merged = first.Compute(), direct = all.Compute();
  EXPECT_EQ(merged.count, 5);
  EXPECT_EQ(merged.mean, direct.mean);
  EXPECT_EQ(merged.std, direct.std);
  EXPECT_EQ(merged.q50, direct.q50);
  EXPECT_THROW(NumericStats(2).Compute(), std::logic_error);
}

TEST(ImageStats, PerChannelInUnitRangeFromTheFrames) {
  // Two 2x1 frames: red channel 0 and 255, green 51 everywhere, blue 0, 0, 102, 102.
  const uint8_t first[] = {0, 51, 0, 255, 51, 0};
  const uint8_t second[] = {0, 51, 102, 255, 51, 102};
  ImageStats stats;
  stats.AddFrame(first, 2, 1);
  stats.AddFrame(second, 2, 1);
  const FeatureStats result = stats.Compute();
  EXPECT_EQ(result.count, 2);
  EXPECT_DOUBLE_EQ(result.min[0], 0.0);
  EXPECT_DOUBLE_EQ(result.max[0], 1.0);
  EXPECT_DOUBLE_EQ(result.mean[0], 0.5);
  EXPECT_DOUBLE_EQ(result.std[0], 0.5);
  EXPECT_DOUBLE_EQ(result.mean[1], 0.2);
  EXPECT_DOUBLE_EQ(result.std[1], 0.0);
  EXPECT_DOUBLE_EQ(result.q50[2], 0.2);  // the median of 0, 0, 102, 102 is 51
  EXPECT_DOUBLE_EQ(result.q10[0], 0.0);  // 0, 0, 255, 255 at 0.1 -> rank 0.3
  EXPECT_DOUBLE_EQ(result.q90[0], 1.0);
}

TEST(ImageStats, LargeFramesAreSampledOnAGridOfAbout150Pixels) {
  std::vector<uint8_t> frame(640 * 480 * 3, 0);
  // Only pixels off the 4-pixel grid are white: the sampled statistics see none of them.
  for (int y = 0; y < 480; ++y) {
    for (int x = 0; x < 640; ++x) {
      if (x % 4 != 0 || y % 4 != 0) frame[(static_cast<std::size_t>(y) * 640 + x) * 3] = 255;
    }
  }
  ImageStats stats;
  stats.AddFrame(frame.data(), 640, 480);
  EXPECT_DOUBLE_EQ(stats.Compute().max[0], 0.0);
}

}  // namespace
}  // namespace tavis::batch::dataset

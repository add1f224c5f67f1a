#include "engine/random.h"

#include <gtest/gtest.h>

#include <cmath>

namespace tavis::engine {
namespace {

TEST(RandomStream, SameKeySameNumbersOtherKeysDiffer) {
  RandomStream a(7, RandomStreamId::kTask, 3);
  RandomStream b(7, RandomStreamId::kTask, 3);
  RandomStream other_episode(7, RandomStreamId::kTask, 4);
  RandomStream other_stream(7, RandomStreamId::kInitPose, 3);
  for (int i = 0; i < 100; ++i) {
    const double x = a.Uniform();
    EXPECT_EQ(x, b.Uniform());
    EXPECT_NE(x, other_episode.Uniform());
    EXPECT_NE(x, other_stream.Uniform());
  }
}

TEST(RandomStream, UniformAndNormalHaveTheRightMoments) {
  RandomStream rng(1, RandomStreamId::kTask, 0);
  const int n = 200000;
  double sum = 0.0, sum_normal = 0.0, sum_normal_sq = 0.0;
  for (int i = 0; i < n; ++i) {
    const double u = rng.Uniform(2.0, 4.0);
    ASSERT_GE(u, 2.0);
    ASSERT_LT(u, 4.0);
    sum += u;
    const double z = rng.Normal(1.0, 0.5);
    sum_normal += z;
    sum_normal_sq += (z - 1.0) * (z - 1.0);
  }
  EXPECT_NEAR(sum / n, 3.0, 0.01);
  EXPECT_NEAR(sum_normal / n, 1.0, 0.01);
  EXPECT_NEAR(std::sqrt(sum_normal_sq / n), 0.5, 0.01);
}

}  // namespace
}  // namespace tavis::engine

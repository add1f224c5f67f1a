#include "scenarios/object_placement.h"

#include <gtest/gtest.h>

namespace tavis::scenarios {
namespace {

PlacementRanges TableRanges(double min_separation) {
  PlacementRanges r;
  r.x = {0.35, 0.45};
  r.y = {-0.25, 0.25};
  r.z = {1.1, 1.1};
  r.roll = {-1.5708, -1.5708};
  r.pitch = {0.0, 0.0};
  r.yaw = {-3.14159, 3.14159};
  r.min_separation = min_separation;
  return r;
}

// With room for everyone the sampler always separates; in the id range six objects often do
// not fit, and the reference then accepts the last try (tested below).
TEST(ObjectPlacement, PlacementsAreInRangeAndSeparatedWhenThereIsRoom) {
  PlacementRanges ranges = TableRanges(0.10);
  ranges.y = {-1.0, 1.0};
  for (uint64_t episode = 0; episode < 200; ++episode) {
    engine::RandomStream rng(3, engine::RandomStreamId::kTask, episode);
    const auto placements = SampleSeparatedPlacements(ranges, 6, rng);
    ASSERT_EQ(placements.size(), 6u);
    for (size_t i = 0; i < placements.size(); ++i) {
      EXPECT_GE(placements[i].position.x(), 0.35);
      EXPECT_LE(placements[i].position.x(), 0.45);
      EXPECT_DOUBLE_EQ(placements[i].position.z(), 1.1);
      for (size_t j = 0; j < i; ++j) EXPECT_GT((placements[i].position - placements[j].position).norm(), 0.10);
    }
  }
}

TEST(ObjectPlacement, ImpossibleSeparationAcceptsTheLastTry) {
  engine::RandomStream rng(3, engine::RandomStreamId::kTask, 0);
  const auto placements = SampleSeparatedPlacements(TableRanges(10.0), 3, rng);
  EXPECT_EQ(placements.size(), 3u);
  // 1 draw set for the first object, then 5000 tries (6 draws each) for each other object.
  EXPECT_EQ(rng.counter(), 6u * (1 + 2 * 5000));
}

}  // namespace
}  // namespace tavis::scenarios

#include "scenarios/peeking_box.h"

#include <gtest/gtest.h>

#include "scenarios/registry.h"
#include "scenarios/task_state.h"

namespace tavis::scenarios {
namespace {

constexpr int kBack = 5, kFront = 6, kLid = 7, kPosY = 8, kNegY = 9;

TEST(PeekingBox, OneSideWallIsMissingAndTheObjectIsInside) {
  const ScenarioDef& scenario = FindScenario("peeking-box");
  engine::WorldModel model;
  scenario.layout(model);
  ASSERT_EQ(model.num_objects(), 10);
  for (int wall = kBack; wall <= kNegY; ++wall) {
    EXPECT_EQ(model.objects[wall].motion, engine::ObjectMotion::kKinematic);
    EXPECT_TRUE(model.objects[wall].collides);
  }
  engine::BatchState state;
  state.Allocate(1, 17, model.num_objects());
  int open_left = 0;
  for (uint64_t episode = 0; episode < 200; ++episode) {
    state.task_rng[0] = engine::RandomStream(9, engine::RandomStreamId::kTask, episode);
    scenario.reset(model, Split::kId, state, 0);
    const bool left_open = TaskState<PeekingBoxVars>(state, 0).open_side > 0;
    open_left += left_open;
    EXPECT_EQ(state.object_enabled_at(0, kPosY), left_open ? 0 : 1);
    EXPECT_EQ(state.object_enabled_at(0, kNegY), left_open ? 1 : 0);
    for (int wall : {kBack, kFront, kLid}) EXPECT_EQ(state.object_enabled_at(0, wall), 1);
    // Box frame from the front and back panels: centre between them, x axis toward the back.
    const Vec3 front = state.ObjectPosition(0, kFront);
    const Vec3 back = state.ObjectPosition(0, kBack);
    const Vec3 centre = 0.5 * (front + back);
    const Vec3 axis = (back - front).normalized();
    EXPECT_NEAR((back - front).norm(), 0.408, 1e-9);
    EXPECT_LE(std::abs(std::atan2(axis.y(), axis.x())), 5.0 * M_PI / 180.0 + 1e-9);
    EXPECT_NEAR(state.ObjectPosition(0, kLid).z(), 1.199, 1e-12);
    const int target = state.target(0);
    const Vec3 offset = state.ObjectPosition(0, target) - centre;
    const double along = offset.x() * axis.x() + offset.y() * axis.y();
    const double across = -offset.x() * axis.y() + offset.y() * axis.x();
    EXPECT_LE(std::abs(along), 0.04 + 1e-9);
    EXPECT_LE(std::abs(across), 0.02 + 1e-9);
    EXPECT_DOUBLE_EQ(state.ObjectPosition(0, target).z(), 1.05);
  }
  EXPECT_GT(open_left, 70);
  EXPECT_LT(open_left, 130);
}

}  // namespace
}  // namespace tavis::scenarios

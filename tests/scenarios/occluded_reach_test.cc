#include "scenarios/occluded_reach.h"

#include <gtest/gtest.h>

#include "scenarios/registry.h"

namespace tavis::scenarios {
namespace {

TEST(OccludedReach, OneObjectBehindTheScreenInItsSplitRange) {
  const ScenarioDef& scenario = FindScenario("occluded-reach");
  engine::WorldModel model;
  scenario.layout(model);
  ASSERT_EQ(model.num_objects(), 5);
  // Table plus the monitor's base, post and panel; the panel spans z 1.12..1.52 at x 0.27.
  ASSERT_EQ(model.static_parts.size(), 4u);
  const engine::StaticPart& panel = model.static_parts[3];
  EXPECT_EQ(panel.name, "screen_panel");
  EXPECT_NEAR(panel.X_WS.translation().z() - 0.5 * panel.shape.size.z(), 1.12, 1e-12);
  engine::BatchState state;
  state.Allocate(1, 17, model.num_objects());
  for (const Split split : {Split::kId, Split::kOodSpatial}) {
    const double y_max = split == Split::kId ? 0.20 : 0.30;
    const double x_min = split == Split::kId ? 0.40 : 0.36;
    for (uint64_t episode = 0; episode < 100; ++episode) {
      state.task_rng[0] = engine::RandomStream(7, engine::RandomStreamId::kTask, episode);
      scenario.reset(model, split, state, 0);
      const int target = state.target(0);
      int enabled = 0;
      for (int object = 0; object < 5; ++object) enabled += state.object_enabled_at(0, object);
      EXPECT_EQ(enabled, 1);
      EXPECT_EQ(state.object_enabled_at(0, target), 1);
      const Vec3 p = state.ObjectPosition(0, target);
      EXPECT_GE(p.x(), x_min);
      EXPECT_LE(std::abs(p.y()), y_max);
      EXPECT_DOUBLE_EQ(p.z(), 1.1);
    }
  }
}

TEST(OccludedReach, SuccessNeedsTheHigherLift) {
  const ScenarioDef& scenario = FindScenario("occluded-reach");
  engine::WorldModel model;
  scenario.layout(model);
  engine::BatchState state;
  state.Allocate(1, 17, model.num_objects());
  state.task[0].target = 2;
  state.object_pose_row(0, 2)[2] = 1.22;  // enough for the clutter tasks, not for this one
  EXPECT_FALSE(scenario.Succeeded(state, 0));
  state.object_pose_row(0, 2)[2] = 1.26;
  EXPECT_TRUE(scenario.Succeeded(state, 0));
}

}  // namespace
}  // namespace tavis::scenarios

#include "scenarios/multi_shelf_scan.h"

#include <gtest/gtest.h>

#include <array>
#include <set>

#include "scenarios/registry.h"

namespace tavis::scenarios {
namespace {

TEST(MultiShelfScan, CabinetWithoutTableAndItsOwnLight) {
  engine::WorldModel model;
  FindScenario("multi-shelf-scan").layout(model);
  ASSERT_EQ(model.static_parts.size(), 7u);
  for (const engine::StaticPart& part : model.static_parts) EXPECT_NE(part.name, "table");
  // Board top surfaces 0.98, 1.11, 1.28; the front edge at x = 0.465.
  const engine::StaticPart& board = model.static_parts[1];
  EXPECT_NEAR(board.X_WS.translation().z() + 0.5 * board.shape.size.z(), 1.11, 1e-12);
  EXPECT_NEAR(board.X_WS.translation().x() - 0.5 * board.shape.size.x(), 0.465, 1e-12);
  EXPECT_DOUBLE_EQ(model.lighting.distant_intensity, 1000.0);
}

TEST(MultiShelfScan, FiveObjectsInFiveDistinctSlots) {
  const std::array<double, 3> kShelfHeights = {0.97, 1.10, 1.27};
  const ScenarioDef& scenario = FindScenario("multi-shelf-scan");
  engine::WorldModel model;
  scenario.layout(model);
  engine::BatchState state;
  state.Allocate(1, 17, model.num_objects());
  for (uint64_t episode = 0; episode < 100; ++episode) {
    state.task_rng[0] = engine::RandomStream(5, engine::RandomStreamId::kTask, episode);
    scenario.reset(model, Split::kId, state, 0);
    std::set<std::pair<int, int>> slots;
    for (int object = 0; object < 5; ++object) {
      EXPECT_EQ(state.object_enabled_at(0, object), 1);
      const Vec3 p = state.ObjectPosition(0, object);
      EXPECT_GE(p.x(), 0.49);
      EXPECT_LE(p.x(), 0.55);
      const double height_over_board = p.z() - 0.05;
      const int shelf = height_over_board < 1.0 ? 0 : height_over_board < 1.2 ? 1 : 2;
      EXPECT_NEAR(height_over_board, kShelfHeights[static_cast<std::size_t>(shelf)], 1e-12);
      EXPECT_LE(std::abs(std::abs(p.y()) - 0.15), 0.03 + 1e-12);
      slots.insert({shelf, p.y() > 0.0});
    }
    EXPECT_EQ(slots.size(), 5u);
  }
}

TEST(MultiShelfScan, SuccessIsPullingTheTargetPastTheShelfFront) {
  const ScenarioDef& scenario = FindScenario("multi-shelf-scan");
  engine::WorldModel model;
  scenario.layout(model);
  engine::BatchState state;
  state.Allocate(1, 17, model.num_objects());
  state.task[0].target = 1;
  state.object_pose_row(0, 1)[0] = 0.44;
  EXPECT_FALSE(scenario.Succeeded(state, 0));
  state.object_pose_row(0, 1)[0] = 0.43;
  EXPECT_TRUE(scenario.Succeeded(state, 0));
}

}  // namespace
}  // namespace tavis::scenarios

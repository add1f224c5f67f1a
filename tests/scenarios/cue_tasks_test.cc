// conditional-pick and wait-then-act: the tasks whose cue (card, light) decides what to do.
#include <gtest/gtest.h>

#include "scenarios/registry.h"

namespace tavis::scenarios {
namespace {

constexpr int kCue = 5;  // the card or the light, after the five YCB objects

struct TaskBatch {
  const ScenarioDef& scenario;
  engine::WorldModel model;
  engine::BatchState state;

  explicit TaskBatch(const std::string& task) : scenario(FindScenario(task)) {
    scenario.layout(model);
    state.Allocate(1, 17, model.num_objects());
  }
  void Reset(Split split, uint64_t episode) {
    state.task_rng[0] = engine::RandomStream(11, engine::RandomStreamId::kTask, episode);
    scenario.reset(model, split, state, 0);
  }
  int Target() const { return state.target(0); }
};

TEST(ConditionalPick, RedCardMeansLeftGreenMeansRight) {
  TaskBatch task("conditional-pick");
  ASSERT_EQ(task.model.objects[kCue].motion, engine::ObjectMotion::kKinematic);
  EXPECT_FALSE(task.model.objects[kCue].collides);
  int red = 0;
  for (uint64_t episode = 0; episode < 200; ++episode) {
    task.Reset(Split::kId, episode);
    int enabled = 0;
    for (int object = 0; object < 5; ++object) enabled += task.state.object_enabled_at(0, object);
    EXPECT_EQ(enabled, 2);
    const float* rgb = task.state.object_rgb_row(0, kCue);
    const bool is_red = rgb[0] == 1.0f && rgb[1] == 0.0f;
    EXPECT_TRUE(is_red || (rgb[0] == 0.0f && rgb[1] == 1.0f));
    red += is_red;
    const Vec3 target = task.state.ObjectPosition(0, task.Target());
    EXPECT_EQ(target.y() > 0.0, is_red) << "red: left (y > 0); green: right";
    EXPECT_GE(std::abs(target.y()), 0.15);
    const Vec3 card = task.state.ObjectPosition(0, kCue);
    EXPECT_LE(std::abs(card.y()), 0.05);
    EXPECT_DOUBLE_EQ(card.z(), 1.002);
  }
  EXPECT_GT(red, 70);
  EXPECT_LT(red, 130);
}

TEST(WaitThenAct, LightTurnsGreenAfterItsDelayAndOnlyThenCountsSuccess) {
  TaskBatch task("wait-then-act");
  for (uint64_t episode = 0; episode < 50; ++episode) {
    task.Reset(Split::kId, episode);
    const double green_step = task.state.task[0].go_policy_step;
    EXPECT_GE(green_step, 40.0);  // 2..5 s at 20 Hz
    EXPECT_LE(green_step, 100.0);
    EXPECT_EQ(task.state.object_rgb_row(0, kCue)[0], 1.0f);
    // The target held high from the start: no success while the light is red.
    task.state.object_pose_row(0, task.Target())[2] = 1.3;
    const int green_tick = static_cast<int>(green_step) * task.model.physics.controls_per_policy();
    for (int tick = 1; tick <= green_tick; ++tick) {
      task.state.control_step[0] = tick;
      task.scenario.update(task.model, task.state, 0);
      const bool green = task.state.task[0].go;
      EXPECT_EQ(green, tick == green_tick) << "tick " << tick;
      EXPECT_EQ(task.scenario.Succeeded(task.state, 0), green);
    }
    EXPECT_EQ(task.state.object_rgb_row(0, kCue)[1], 1.0f);
  }
}

TEST(WaitThenAct, OodSplitWidensTheDelay) {
  TaskBatch task("wait-then-act");
  double longest = 0.0;
  for (uint64_t episode = 0; episode < 200; ++episode) {
    task.Reset(Split::kOodSpatial, episode);
    longest = std::max(longest, static_cast<double>(task.state.task[0].go_policy_step));
  }
  EXPECT_GT(longest, 100.0);
  EXPECT_LE(longest, 160.0);
}

}  // namespace
}  // namespace tavis::scenarios

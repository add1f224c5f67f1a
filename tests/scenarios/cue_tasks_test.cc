// conditional-pick and wait-then-act: the tasks whose cue (card, light) decides what to do.
#include <gtest/gtest.h>

#include "engine/object_catalog.h"
#include "scenarios/registry.h"
#include "scenarios/task_state.h"
#include "scenarios/wait_then_act.h"

namespace tavis::scenarios {
namespace {

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
  int Cue() const { return model.ObjectIndex(scenario.cue_objects.at(0)); }  // the card or the light
};

TEST(ConditionalPick, RedCardMeansLeftGreenMeansRight) {
  TaskBatch task("conditional-pick");
  ASSERT_EQ(task.model.objects[task.Cue()].motion, engine::ObjectMotion::kKinematic);
  EXPECT_FALSE(task.model.objects[task.Cue()].collides);
  int red = 0;
  for (uint64_t episode = 0; episode < 200; ++episode) {
    task.Reset(Split::kId, episode);
    int enabled = 0;
    for (int object = 0; object < 5; ++object) enabled += task.state.object_enabled_at(0, object);
    EXPECT_EQ(enabled, 2);
    const float* rgb = task.state.object_rgb_row(0, task.Cue());
    const bool is_red = rgb[0] == 1.0f && rgb[1] == 0.0f;
    EXPECT_TRUE(is_red || (rgb[0] == 0.0f && rgb[1] == 1.0f));
    red += is_red;
    const Vec3 target = task.state.ObjectPosition(0, task.Target());
    EXPECT_EQ(target.y() > 0.0, is_red) << "red: left (y > 0); green: right";
    EXPECT_GE(std::abs(target.y()), 0.15);
    const Vec3 card = task.state.ObjectPosition(0, task.Cue());
    EXPECT_LE(std::abs(card.y()), 0.05);
    EXPECT_DOUBLE_EQ(card.z(), 1.002);
  }
  EXPECT_GT(red, 70);
  EXPECT_LT(red, 130);
}

// The cue is found by its name, not by its place in the object list: with another object laid
// out before it, a reset still places and colours the card or the light, and the object before
// it is left alone.
TEST(CueTasks, TheCueIsFoundByNameWhereverTheLayoutPutsIt) {
  for (const char* name : {"conditional-pick", "wait-then-act"}) {
    SCOPED_TRACE(name);
    const ScenarioDef& scenario = FindScenario(name);
    engine::WorldModel model;
    scenario.layout(model);
    const int laid_out_at = model.ObjectIndex(scenario.cue_objects.at(0));
    model.objects.insert(model.objects.begin() + laid_out_at, engine::MakeCatalogObject("red_cube"));
    const int cue = model.ObjectIndex(scenario.cue_objects.at(0));
    ASSERT_EQ(cue, laid_out_at + 1);
    engine::BatchState state;
    state.Allocate(1, 17, model.num_objects());
    state.task_rng[0] = engine::RandomStream(11, engine::RandomStreamId::kTask, 0);
    scenario.reset(model, Split::kId, state, 0);
    const float* rgb = state.object_rgb_row(0, cue);
    EXPECT_EQ(rgb[0] + rgb[1], 1.0f) << "the cue shows red or green";
    EXPECT_GT(state.ObjectPosition(0, cue).z(), 1.0) << "the cue stands on the table";
    EXPECT_LT(state.object_rgb_row(0, laid_out_at)[0], 0.0f) << "the object before it keeps its palette colour";
    EXPECT_EQ(state.ObjectPosition(0, laid_out_at).z(), 0.0) << "and is not placed as the cue";
  }
}

TEST(WaitThenAct, LightTurnsGreenAfterItsDelayAndOnlyThenCountsSuccess) {
  TaskBatch task("wait-then-act");
  for (uint64_t episode = 0; episode < 50; ++episode) {
    task.Reset(Split::kId, episode);
    const double green_step = TaskState<WaitThenActVars>(task.state, 0).go_policy_step;
    EXPECT_GE(green_step, 40.0);  // 2..5 s at 20 Hz
    EXPECT_LE(green_step, 100.0);
    EXPECT_EQ(task.state.object_rgb_row(0, task.Cue())[0], 1.0f);
    // The target held high from the start: no success while the light is red.
    task.state.object_pose_row(0, task.Target())[2] = 1.3;
    const int green_tick = static_cast<int>(green_step) * task.model.physics.controls_per_policy();
    for (int tick = 1; tick <= green_tick; ++tick) {
      task.state.control_step[0] = tick;
      task.scenario.update(task.model, task.state, 0);
      const bool green = TaskState<WaitThenActVars>(task.state, 0).go;
      EXPECT_EQ(green, tick == green_tick) << "tick " << tick;
      EXPECT_EQ(task.scenario.Succeeded(task.state, 0), green);
    }
    EXPECT_EQ(task.state.object_rgb_row(0, task.Cue())[1], 1.0f);
  }
}

TEST(WaitThenAct, OodSplitWidensTheDelay) {
  TaskBatch task("wait-then-act");
  double longest = 0.0;
  for (uint64_t episode = 0; episode < 200; ++episode) {
    task.Reset(Split::kOodSpatial, episode);
    longest = std::max(longest, static_cast<double>(TaskState<WaitThenActVars>(task.state, 0).go_policy_step));
  }
  EXPECT_GT(longest, 100.0);
  EXPECT_LE(longest, 160.0);
}

}  // namespace
}  // namespace tavis::scenarios

// The profiler as the episode loop's observer: what each hook adds to the profile, and a profiled
// run's profile on either schedule (every stage, every episode, every section).
#include "batch/cell/cell_profiler.h"

#include <gtest/gtest.h>

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "batch/builtin_policies.h"
#include "batch/episode_driver.h"
#include "scenarios/registry.h"
#include "tests/support/idle_policy.h"
#include "tests/support/robot_loading.h"

namespace tavis::batch::cell {
namespace {

constexpr double kNap = 0.005;  // seconds slept inside a part of the loop

VecEnv ShortEpisodes(int slots) {
  const scenarios::ScenarioDef& scenario = scenarios::FindScenario("clutter-pick-cube");
  engine::WorldModel model = BuildWorldModel(tavis::testing::LoadRobot("gr1t2"), scenario);
  model.physics.episode_length_s = 0.25;  // 15 control ticks
  return VecEnv(std::move(model), scenario, scenarios::Split::kId, slots, 1);
}

void Nap() { std::this_thread::sleep_for(std::chrono::duration<double>(kNap)); }

void NapAsPart(CellProfiler& profiler, LoopPart part, int slot) {
  profiler.PartStarting(part, slot);
  Nap();
  profiler.PartEnded(part, slot);
}

// The profile's stages by name (at() throws for a stage it lacks).
std::map<std::string, double> Stages(const CellProfile& profile) {
  return std::map<std::string, double>(profile.stages.begin(), profile.stages.end());
}

TEST(CellProfiler, LockStepCountsSinksAndABatchedPolicyAndLeavesParallelWorkOutOfTheSerialTime) {
  VecEnv vec_env = ShortEpisodes(2);
  testing::IdlePolicy policy;  // answers the whole batch: its time is its parts' wall time
  CellProfiler profiler;
  profiler.RunStarting(vec_env, policy, /*per_slot=*/false);
  NapAsPart(profiler, LoopPart::kSinks, kWholeBatch);
  NapAsPart(profiler, LoopPart::kPolicyActs, kWholeBatch);
  NapAsPart(profiler, LoopPart::kParallel, kWholeBatch);
  profiler.RunEnded();
  const CellProfile& profile = profiler.profile();
  EXPECT_FALSE(profile.per_slot);
  EXPECT_GE(Stages(profile).at("recording"), kNap);
  EXPECT_GE(Stages(profile).at("policy"), kNap);
  EXPECT_LE(Stages(profile).at("policy"), profile.wall_seconds - 2 * kNap)
      << "the sinks' and the parallel part are not";
  EXPECT_GE(profile.wall_seconds, 3 * kNap);
  // Serial: everything but the policy's and the parallel part, the sinks included.
  EXPECT_GE(profile.serial_seconds, kNap);
  EXPECT_LE(profile.serial_seconds, profile.wall_seconds - 2 * kNap);
  EXPECT_NEAR(Stages(profile).at("driver"), profile.serial_seconds - Stages(profile).at("recording"), 1e-9);
}

TEST(CellProfiler, PerSlotASlotsSinksCountWhenItsEpisodeEndsAndTheEndIsSerial) {
  VecEnv vec_env = ShortEpisodes(2);
  std::unique_ptr<Policy> hold = MakeBuiltinPolicy("hold", vec_env.scenario(), vec_env.model(), 2);
  CellProfiler profiler;
  profiler.RunStarting(vec_env, *hold, /*per_slot=*/true);
  profiler.PartStarting(LoopPart::kParallel, kWholeBatch);
  vec_env.ResetEnv(1, 4);
  profiler.EnvReset(1);
  NapAsPart(profiler, LoopPart::kSinks, 1);
  profiler.EpisodeEnding(1);
  Nap();  // the sinks told of the end
  profiler.EpisodeEnded(1);
  profiler.PartEnded(LoopPart::kParallel, kWholeBatch);
  profiler.RunEnded();
  const CellProfile& profile = profiler.profile();
  EXPECT_TRUE(profile.per_slot);
  ASSERT_EQ(profile.episodes.size(), 1u);
  EXPECT_EQ(profile.episodes[0].episode, 4);
  EXPECT_EQ(profile.episodes[0].slot, 1);
  EXPECT_GT(profile.episodes[0].seconds, 0.0) << "the slot's reset is its episode's cost";
  EXPECT_DOUBLE_EQ(Stages(profile).at("reset"), profile.episodes[0].seconds);
  EXPECT_GE(Stages(profile).at("recording"), 2 * kNap) << "the slot's sinks and its end";
  EXPECT_GE(profile.serial_seconds, kNap) << "ends are told one at a time";
  EXPECT_LE(profile.serial_seconds, profile.wall_seconds - kNap) << "the slot's sinks ran in the parallel part";
  EXPECT_TRUE(profile.sections.empty());
}

// A profiled run of the hold policy: 5 episodes of 15 ticks on 2 slots, `threads` allowed.
CellProfile HoldRun(bool lock_step, std::size_t threads = 2) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  VecEnv vec_env = ShortEpisodes(2);
  std::unique_ptr<Policy> hold = MakeBuiltinPolicy("hold", vec_env.scenario(), vec_env.model(), 2);
  EpisodeDriver driver(vec_env, *hold, 5);
  if (lock_step) driver.RequireLockStep();
  CellProfiler profiler;
  driver.SetObserver(profiler);
  driver.Run();
  return profiler.profile();
}

TEST(CellProfiler, AProfiledRunHasEveryStageEpisodeAndSectionOnEitherSchedule) {
  for (const bool lock_step : {true, false}) {
    const CellProfile profile = HoldRun(lock_step);
    const char* label = lock_step ? "lock-step" : "per slot";
    std::vector<std::string> names;
    for (const auto& [name, seconds] : profile.stages) {
      names.push_back(name);
      EXPECT_GE(seconds, 0.0) << label << ", " << name;
    }
    std::vector<std::string> expected = {"apply_actions", "step_physics", "servo_neck", "update_task",
                                         "end_episodes",  "reset",        "render",     "render_idle",
                                         "policy",        "recording",    "driver"};
    if (!lock_step) expected.erase(expected.begin() + 7);  // per slot no thread idles in a batch render call
    EXPECT_EQ(names, expected) << label;
    EXPECT_EQ(profile.per_slot, !lock_step);
    EXPECT_GT(Stages(profile).at("step_physics"), 0.0) << label;
    EXPECT_GT(Stages(profile).at("reset"), 0.0) << label;
    std::set<int64_t> episodes;
    for (const EpisodeCost& cost : profile.episodes) {
      episodes.insert(cost.episode);
      EXPECT_EQ(cost.control_ticks, 15) << label;
      EXPECT_GT(cost.seconds, 0.0) << label << ", episode " << cost.episode;
    }
    EXPECT_EQ(episodes, (std::set<int64_t>{0, 1, 2, 3, 4})) << label << ": every episode once";
    EXPECT_EQ(profile.episodes.size(), 5u) << label;
    // Lock-step: a section per tick (45: three rounds of 15) and per refill (3).
    EXPECT_EQ(profile.sections.size(), lock_step ? 48u : 0u) << label;
    EXPECT_GT(profile.wall_seconds, 0.0) << label;
    EXPECT_LE(profile.serial_seconds, profile.wall_seconds + 1e-9) << label;
  }
}

// `--threads 1` sets a process-wide limit of one thread; the profile must say 1 whatever the
// machine's cores (it once reported the default arena's size, which is the number of cores).
TEST(CellProfiler, AProfileCountsTheThreadsTheLimitAllowsNotTheMachinesCores) {
  for (const bool lock_step : {true, false}) {
    EXPECT_EQ(HoldRun(lock_step, 1).threads, 1) << (lock_step ? "lock-step" : "per slot");
    EXPECT_EQ(HoldRun(lock_step, 2).threads, std::min(2, tbb::this_task_arena::max_concurrency()))
        << (lock_step ? "lock-step" : "per slot");
  }
}

}  // namespace
}  // namespace tavis::batch::cell

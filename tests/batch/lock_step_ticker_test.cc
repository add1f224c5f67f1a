// The lock-step loop's steps driven directly, as the Python module's env drives them: episodes
// started where the caller says, ticks with the caller's actions, ends told once.
#include "batch/lock_step_ticker.h"

#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "batch/builtin_policies.h"
#include "batch/episode_slots.h"
#include "scenarios/registry.h"
#include "tests/support/idle_policy.h"
#include "tests/support/robot_loading.h"

namespace tavis::batch {
namespace {

// clutter-pick-cube with episodes of 0.25 s: 15 control ticks to the time-out.
VecEnv ShortEpisodes(int slots) {
  const scenarios::ScenarioDef& scenario = scenarios::FindScenario("clutter-pick-cube");
  engine::WorldModel model = BuildWorldModel(tavis::testing::LoadRobot("gr1t2"), scenario);
  model.physics.episode_length_s = 0.25;
  return VecEnv(std::move(model), scenario, scenarios::Split::kId, slots, 1);
}

// What the sinks are told, in order: "S<slot>:<episode>" started, "E<slot>:<episode>" ended;
// and how many actions and steps they saw, with the last action of each slot. Optionally done
// with each episode after a number of ticks.
class Log : public EpisodeSink {
 public:
  explicit Log(int stop_after_ticks) : stop_after_ticks_(stop_after_ticks) {}
  void EpisodeStarted(const VecEnv& vec_env, int slot) override { Add("S", vec_env, slot); }
  void TickStarting(const VecEnv&) override { ++ticks_started; }
  void ActionChosen(const VecEnv&, int slot, const kinematics::Action& action) override {
    ++actions;
    last_action[slot] = action;
  }
  void Stepped(const VecEnv&) override { ++stepped; }
  bool EpisodeComplete(const VecEnv& vec_env, int slot) const override {
    return stop_after_ticks_ >= 0 && vec_env.state().control_step[slot] >= stop_after_ticks_;
  }
  void EpisodeEnded(const VecEnv& vec_env, int slot) override { Add("E", vec_env, slot); }

  std::vector<std::string> events;
  int ticks_started = 0;
  int actions = 0;
  int stepped = 0;
  std::map<int, kinematics::Action> last_action;

 private:
  void Add(const char* kind, const VecEnv& vec_env, int slot) {
    events.push_back(kind + std::to_string(slot) + ":" + std::to_string(vec_env.state().episode[slot]));
  }
  int stop_after_ticks_;
};

// A ticker on `slots` short-episode slots with a Log sink and the hold policy reset with its
// starts, whose actions HoldActions fills for the running slots.
struct Rig {
  explicit Rig(int slots, CameraProtocol protocol = CameraProtocol::kHead, int stop_after_ticks = -1)
      : vec_env(ShortEpisodes(slots)),
        episode_slots(vec_env),
        log(stop_after_ticks),
        ticker(episode_slots),
        hold(MakeBuiltinPolicy("hold", vec_env.scenario(), vec_env.model(), slots)),
        actions(static_cast<std::size_t>(slots), kinematics::Action{}) {
    episode_slots.SetCameraProtocol(protocol);
    episode_slots.AddSink(log);
    ticker.AddPolicy(*hold);
  }
  void HoldActions() {
    const engine::BatchState& state = vec_env.state();
    std::vector<uint8_t> acting(static_cast<std::size_t>(state.num_envs), 0);
    for (int slot = 0; slot < state.num_envs; ++slot) acting[slot] = state.running(slot) ? 1 : 0;
    hold->Act(episode_slots.observation(), acting, actions);
  }

  VecEnv vec_env;
  EpisodeSlots episode_slots;
  Log log;
  LockStepTicker ticker;
  std::unique_ptr<Policy> hold;
  ActionBatch actions;
};

TEST(LockStepTicker, TellsEachEndOnceAndAnEndedSlotStaysEndedUntilStartedAgain) {
  Rig rig(2);
  LockStepTicker& ticker = rig.ticker;
  ticker.StartEpisodes({{1, 7}, {0, 3}});
  EXPECT_EQ(rig.log.events, (std::vector<std::string>{"S1:7", "S0:3"})) << "in the order listed";
  EXPECT_EQ(ticker.RunningEnvs(), 2);
  EXPECT_STREQ(rig.episode_slots.prompt(0), rig.vec_env.scenario().prompt(rig.vec_env.state(), 0));
  std::vector<int> told;
  const auto collect = [&] { ticker.CollectEnded([&](int slot) { told.push_back(slot); }); };
  for (int tick = 0; tick < 15; ++tick) {
    collect();
    EXPECT_TRUE(told.empty()) << "nothing has ended before the time-out, tick " << tick;
    ticker.TickStarting();
    rig.HoldActions();
    ticker.Tick(rig.actions, rig.hold.get());
  }
  EXPECT_EQ(ticker.RunningEnvs(), 0);
  EXPECT_EQ(ticker.control_ticks(), 2 * 15);
  EXPECT_EQ(rig.log.actions, 2 * 15);
  EXPECT_EQ(rig.log.ticks_started, 15);
  EXPECT_EQ(rig.log.stepped, 15);

  collect();
  EXPECT_EQ(told, (std::vector<int>{0, 1})) << "in slot order";
  EXPECT_EQ(rig.log.events, (std::vector<std::string>{"S1:7", "S0:3", "E0:3", "E1:7"}));
  EXPECT_EQ(rig.vec_env.state().end[0], engine::EpisodeEnd::kTimeOut);
  collect();
  EXPECT_EQ(told.size(), 2u) << "an end is told once";
  EXPECT_EQ(rig.vec_env.state().episode[1], 7) << "the ended slot keeps its episode until started again";
  EXPECT_TRUE(rig.episode_slots.told_ended(1));

  ticker.Tick(rig.actions, rig.hold.get());
  EXPECT_EQ(ticker.control_ticks(), 2 * 15) << "ended slots do not tick";
  EXPECT_EQ(rig.log.actions, 2 * 15);

  ticker.StartEpisodes({{1, 8}});
  EXPECT_FALSE(rig.episode_slots.told_ended(1));
  EXPECT_EQ(ticker.RunningEnvs(), 1);
  while (ticker.RunningEnvs() > 0) {
    rig.HoldActions();
    ticker.Tick(rig.actions, rig.hold.get());
  }
  collect();
  EXPECT_EQ(told, (std::vector<int>{0, 1, 1}));
  EXPECT_EQ(rig.log.events.back(), "E1:8");
  EXPECT_EQ(ticker.control_ticks(), 3 * 15);
}

TEST(LockStepTicker, AppliesTheCameraProtocolBeforeTheSinksSeeTheActionAndTheWorldStepsWithIt) {
  Rig rig(2, CameraProtocol::kFixed);
  rig.ticker.StartEpisodes({{0, 0}, {1, 1}});
  rig.HoldActions();
  for (kinematics::Action& action : rig.actions) action[kinematics::action::kNeckYaw] = 0.7;
  rig.ticker.Tick(rig.actions, nullptr);
  for (int slot = 0; slot < 2; ++slot) {
    EXPECT_EQ(rig.log.last_action[slot][kinematics::action::kNeckYaw], 0.0) << "slot " << slot;
    EXPECT_EQ(rig.actions[slot][kinematics::action::kNeckYaw], 0.0) << "the world stepped with the rule applied";
  }
}

// A policy that could not act for slot 0 and has given up on slot 1.
class FaultingPolicy : public testing::IdlePolicy {
 public:
  void TakeFaults(std::vector<PolicyFault>& faults) override { faults.push_back({0, "reply had no actions"}); }
  bool GaveUp(int env) const override { return env == 1; }
};

TEST(LockStepTicker, EndsTheEpisodesThePolicyCouldNotActForOrGaveUpOnOnlyWhenGivenThePolicy) {
  Rig rig(2);
  rig.ticker.StartEpisodes({{0, 0}, {1, 1}});
  rig.HoldActions();
  rig.ticker.Tick(rig.actions, nullptr);
  EXPECT_EQ(rig.ticker.RunningEnvs(), 2) << "actions from elsewhere: no policy faults or gives up";

  FaultingPolicy faulting;
  rig.ticker.Tick(rig.actions, &faulting);
  const engine::BatchState& state = rig.vec_env.state();
  EXPECT_EQ(state.end[0], engine::EpisodeEnd::kInvalidAction);
  EXPECT_EQ(state.invalid_action[0].reason, "reply had no actions");
  EXPECT_EQ(state.control_step[0], 1) << "ended before this tick's step";
  EXPECT_EQ(state.end[1], engine::EpisodeEnd::kGaveUp);
  EXPECT_EQ(state.control_step[1], 2) << "ended after this tick's step";
  EXPECT_EQ(rig.ticker.control_ticks(), 4) << "counted as the ticks the policy was asked for";
}

TEST(LockStepTicker, StopsTheEpisodesASinkIsDoneWithWhenCollecting) {
  Rig rig(1, CameraProtocol::kHead, /*stop_after_ticks=*/2);
  rig.ticker.StartEpisodes({{0, 5}});
  int told = 0;
  for (int tick = 0; tick < 4 && told == 0; ++tick) {
    rig.ticker.CollectEnded([&](int) { ++told; });
    rig.HoldActions();
    rig.ticker.Tick(rig.actions, rig.hold.get());
  }
  EXPECT_EQ(told, 1);
  EXPECT_EQ(rig.vec_env.state().end[0], engine::EpisodeEnd::kStopped);
  EXPECT_EQ(rig.vec_env.state().control_step[0], 2);
  EXPECT_EQ(rig.log.events, (std::vector<std::string>{"S0:5", "E0:5"}));
}

}  // namespace
}  // namespace tavis::batch

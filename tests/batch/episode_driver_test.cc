#include "batch/episode_driver.h"

#include <gtest/gtest.h>

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "batch/builtin_policies.h"
#include "batch/cell/cell_profiler.h"
#include "batch/cell/episode_recorder.h"
#include "scenarios/registry.h"
#include "tests/support/altered_hold_policy.h"
#include "tests/support/robot_loading.h"

namespace tavis::batch {
namespace {

engine::WorldModel Model(const std::string& task, double episode_length_s) {
  const kinematics::RobotModel robot = tavis::testing::LoadRobot("gr1t2");
  engine::WorldModel model = BuildWorldModel(robot, scenarios::FindScenario(task));
  model.physics.episode_length_s = episode_length_s;
  return model;
}

// An cell::EpisodeRecorder sink that keeps the env's records, in episode order.
struct RecordCollector {
  explicit RecordCollector(const VecEnv& vec_env, const cell::RecordSettings& settings = cell::RecordSettings())
      : recorder(vec_env.num_envs(), vec_env.model().physics.max_control_steps(), settings, 0,
                 [this](cell::EpisodeRecord&& record) { records.push_back(std::move(record)); }) {}
  std::vector<cell::EpisodeRecord> records;
  cell::EpisodeRecorder recorder;
};

// What a sink saw: each episode's start slot and tick count, in the order of the callbacks.
struct Event {
  char kind;  // 'S' started, 'E' ended
  int slot;
  int64_t episode;
  engine::EpisodeEnd end;
  int control_step;
};

class EventLog : public EpisodeSink {
 public:
  explicit EventLog(int stop_after_ticks = -1) : stop_after_ticks_(stop_after_ticks) {}
  void EpisodeStarted(const VecEnv& vec_env, int slot) override { Add('S', vec_env, slot); }
  void EpisodeEnded(const VecEnv& vec_env, int slot) override {
    Add('E', vec_env, slot);
    final_q.emplace_back(vec_env.state().q_row(slot), vec_env.state().q_row(slot) + vec_env.state().num_joints);
  }
  void ActionChosen(const VecEnv&, int, const kinematics::Action&) override { ++action_ticks; }
  bool EpisodeComplete(const VecEnv& vec_env, int slot) const override {
    return stop_after_ticks_ >= 0 && vec_env.state().control_step[slot] >= stop_after_ticks_;
  }

  std::vector<Event> events;
  std::vector<std::vector<double>> final_q;  // per ended episode, in end order
  int64_t action_ticks = 0;

 private:
  void Add(char kind, const VecEnv& vec_env, int slot) {
    const engine::BatchState& state = vec_env.state();
    events.push_back({kind, slot, state.episode[slot], state.end[slot], state.control_step[slot]});
  }
  int stop_after_ticks_;
};

TEST(EpisodeDriver, RunsEveryEpisodeOnceDealingThemInIndexOrder) {
  VecEnv vec_env(Model("clutter-pick-cube", 0.25), scenarios::FindScenario("clutter-pick-cube"), scenarios::Split::kId,
                 3, 1);
  std::unique_ptr<Policy> hold = MakeBuiltinPolicy("hold", vec_env.scenario(), vec_env.model(), 3);
  EventLog log;
  EpisodeDriver driver(vec_env, *hold, 7);
  driver.AddSink(log);
  std::vector<int64_t> progress;
  driver.SetProgress([&](int64_t finished, int64_t total) {
    EXPECT_EQ(total, 7);
    progress.push_back(finished);
  });
  driver.Run();

  std::vector<int64_t> started, ended;
  for (const Event& event : log.events) (event.kind == 'S' ? started : ended).push_back(event.episode);
  EXPECT_EQ(started, (std::vector<int64_t>{0, 1, 2, 3, 4, 5, 6}));
  ASSERT_EQ(ended.size(), 7u);
  // 0 as the run starts (a progress rate counts from there, not from the first episode to end),
  // then one call per finished episode.
  EXPECT_EQ(progress, (std::vector<int64_t>{0, 1, 2, 3, 4, 5, 6, 7}));
  for (int slot = 0; slot < 3; ++slot) EXPECT_EQ(log.events[static_cast<std::size_t>(slot)].slot, slot);
  // 0.25 s at 60 Hz: every hold episode times out after 15 ticks, and each tick's actions were seen.
  for (const Event& event : log.events) {
    if (event.kind != 'E') continue;
    EXPECT_EQ(event.end, engine::EpisodeEnd::kTimeOut);
    EXPECT_EQ(event.control_step, 15);
  }
  EXPECT_EQ(driver.control_ticks(), 7 * 15);
  EXPECT_EQ(log.action_ticks, 7 * 15);
  for (int slot = 0; slot < 3; ++slot) EXPECT_EQ(vec_env.state().episode[slot], -1) << "slots are released at the end";
}

TEST(EpisodeDriver, StopsAnEpisodeOnceASinkHasWhatItNeeds) {
  VecEnv vec_env(Model("clutter-pick-cube", 2.0), scenarios::FindScenario("clutter-pick-cube"), scenarios::Split::kId,
                 2, 1);
  std::unique_ptr<Policy> hold = MakeBuiltinPolicy("hold", vec_env.scenario(), vec_env.model(), 2);
  EventLog log(/*stop_after_ticks=*/5);
  EpisodeDriver driver(vec_env, *hold, 3, /*first_episode=*/4);
  driver.AddSink(log);
  driver.Run();
  int ended = 0;
  for (const Event& event : log.events) {
    if (event.kind == 'S') {
      EXPECT_GE(event.episode, 4);
    }
    if (event.kind != 'E') continue;
    ++ended;
    EXPECT_EQ(event.end, engine::EpisodeEnd::kStopped);
    EXPECT_EQ(event.control_step, 5);
  }
  EXPECT_EQ(ended, 3);
}

// A batched policy that checks what it is handed: the prompts of the running envs, and that it
// is asked to act exactly on its ticks. Its actions are the reset pose's, from the hold policy.
class CheckingPolicy : public Policy {
 public:
  explicit CheckingPolicy(const VecEnv& vec_env)
      : scenario_(vec_env.scenario()),
        hold_(MakeBuiltinPolicy("hold", vec_env.scenario(), vec_env.model(), vec_env.num_envs())) {}
  std::string name() const override { return "checking"; }
  int control_ticks_per_action() const override { return 3; }
  void Reset(const Observation& observation, const std::vector<uint8_t>& started) override {
    hold_->Reset(observation, started);
  }
  void Act(const Observation& observation, const std::vector<uint8_t>& acting, ActionBatch& actions) override {
    for (int env = 0; env < observation.state.num_envs; ++env) {
      if (!observation.state.running(env)) {
        EXPECT_FALSE(acting[env]);
        continue;
      }
      EXPECT_EQ(acting[env] != 0, observation.state.control_step[env] % 3 == 0);
      ASSERT_NE(observation.prompts[env], nullptr);
      EXPECT_STREQ(observation.prompts[env], scenario_.prompt(observation.state, env)) << "the env's own prompt";
      prompts.emplace_back(observation.prompts[env]);
      acts += acting[env];
    }
    hold_->Act(observation, acting, actions);
  }
  std::vector<std::string> prompts;
  int acts = 0;

 private:
  const scenarios::ScenarioDef& scenario_;
  std::unique_ptr<Policy> hold_;
};

TEST(EpisodeDriver, ABatchedPolicySeesEachEnvsPromptAndActsOnItsTicks) {
  const scenarios::ScenarioDef& scenario = scenarios::FindScenario("clutter-pick-lift");
  VecEnv vec_env(Model("clutter-pick-lift", 0.25), scenario, scenarios::Split::kId, 2, 5);
  CheckingPolicy policy(vec_env);
  EpisodeDriver driver(vec_env, policy, 4);
  driver.Run();
  EXPECT_EQ(policy.acts, 4 * 5) << "15 ticks held 3 at a time";
  EXPECT_EQ(policy.prompts.size(), 4u * 15u) << "every running vec_env's prompt on every tick";
}

TEST(EpisodeDriver, ANonFiniteActionEndsOnlyItsEpisodeNamingTheEntry) {
  VecEnv vec_env(Model("clutter-pick-cube", 0.25), scenarios::FindScenario("clutter-pick-cube"), scenarios::Split::kId,
                 2, 1);
  // The hold policy, except that episode 2 commands a NaN neck yaw on its fourth tick.
  testing::AlteredHoldPolicy policy(
      vec_env, "nan", 1, [](const Observation& observation, int slot, kinematics::Action& action) {
        if (observation.state.episode[slot] == 2 && observation.state.control_step[slot] == 4) {
          action[kinematics::action::kNeckYaw] = std::numeric_limits<double>::quiet_NaN();
        }
      });
  RecordCollector collected(vec_env);
  std::vector<cell::EpisodeRecord>& records = collected.records;
  EpisodeDriver driver(vec_env, policy, 4);
  driver.AddSink(collected.recorder);
  driver.Run();
  ASSERT_EQ(records.size(), 4U);
  for (const cell::EpisodeRecord& record : records) {
    if (record.episode != 2) {
      EXPECT_EQ(record.end, engine::EpisodeEnd::kTimeOut) << "episode " << record.episode;
      continue;
    }
    EXPECT_EQ(record.end, engine::EpisodeEnd::kInvalidAction);
    EXPECT_EQ(record.length_control_ticks, 4) << "ended on the tick of the NaN";
    EXPECT_EQ(record.invalid_action.entry, kinematics::action::kNeckYaw);
    EXPECT_TRUE(std::isnan(record.invalid_action.value));
    EXPECT_EQ(record.invalid_action.reason, "not finite");
  }
}

// The hold policy, except that it cannot act for episode 1: it reports a fault instead.
class FaultyHoldPolicy : public Policy {
 public:
  explicit FaultyHoldPolicy(const VecEnv& vec_env)
      : hold_(MakeBuiltinPolicy("hold", vec_env.scenario(), vec_env.model(), vec_env.num_envs())) {}
  std::string name() const override { return "faulty"; }
  int control_ticks_per_action() const override { return hold_->control_ticks_per_action(); }
  void Reset(const Observation& observation, const std::vector<uint8_t>& started) override {
    hold_->Reset(observation, started);
  }
  void Act(const Observation& observation, const std::vector<uint8_t>& acting, ActionBatch& actions) override {
    hold_->Act(observation, acting, actions);
    for (int env = 0; env < observation.state.num_envs; ++env) {
      if (acting[env] && observation.state.episode[env] == 1) pending_.push_back({env, "reply had no actions"});
    }
  }
  void TakeFaults(std::vector<PolicyFault>& faults) override {
    faults.insert(faults.end(), pending_.begin(), pending_.end());
    pending_.clear();
  }

 private:
  std::unique_ptr<Policy> hold_;
  std::vector<PolicyFault> pending_;
};

TEST(EpisodeDriver, APolicyFaultEndsOnlyItsEpisodeWithTheReason) {
  VecEnv vec_env(Model("clutter-pick-cube", 0.25), scenarios::FindScenario("clutter-pick-cube"), scenarios::Split::kId,
                 2, 1);
  FaultyHoldPolicy policy(vec_env);
  RecordCollector collected(vec_env);
  std::vector<cell::EpisodeRecord>& records = collected.records;
  EpisodeDriver driver(vec_env, policy, 3);
  driver.AddSink(collected.recorder);
  driver.Run();
  ASSERT_EQ(records.size(), 3U);
  EXPECT_EQ(records[0].end, engine::EpisodeEnd::kTimeOut);
  EXPECT_EQ(records[1].end, engine::EpisodeEnd::kInvalidAction);
  EXPECT_EQ(records[1].length_control_ticks, 0) << "ended before its first step";
  EXPECT_EQ(records[1].invalid_action.entry, -1);
  EXPECT_EQ(records[1].invalid_action.reason, "reply had no actions");
  EXPECT_EQ(records[2].end, engine::EpisodeEnd::kTimeOut);
}

// The hold policy, except that in odd episodes it gives up when it acts at tick 6 (hold acts
// every 3 ticks).
class GivingUpHoldPolicy : public PerEnvPolicy {
 public:
  explicit GivingUpHoldPolicy(const VecEnv& vec_env)
      : hold_(MakeBuiltinPolicy("hold", vec_env.scenario(), vec_env.model(), vec_env.num_envs())),
        gave_up_(static_cast<std::size_t>(vec_env.num_envs()), 0) {}
  std::string name() const override { return "giving-up"; }
  int control_ticks_per_action() const override { return hold_->control_ticks_per_action(); }
  bool GaveUp(int env) const override { return gave_up_[static_cast<std::size_t>(env)] != 0; }

 private:
  PerEnvPolicy& hold() const { return dynamic_cast<PerEnvPolicy&>(*hold_); }
  void ResetEnv(const Observation& observation, int env) override {
    hold().ResetOne(observation, env);
    gave_up_[static_cast<std::size_t>(env)] = 0;
  }
  void ActEnv(const Observation& observation, int env, kinematics::Action& action) override {
    hold().ActOne(observation, env, action);
    const engine::BatchState& state = observation.state;
    if (state.episode[env] % 2 == 1 && state.control_step[env] >= 6) gave_up_[static_cast<std::size_t>(env)] = 1;
  }

  std::unique_ptr<Policy> hold_;
  std::vector<uint8_t> gave_up_;
};

TEST(EpisodeDriver, APolicyThatGivesUpEndsItsEpisodeAfterThatTicksStepOnEitherSchedule) {
  for (const bool lock_step : {true, false}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    VecEnv vec_env(Model("clutter-pick-cube", 0.25), scenarios::FindScenario("clutter-pick-cube"),
                   scenarios::Split::kId, 3, 1);
    GivingUpHoldPolicy policy(vec_env);
    RecordCollector collected(vec_env);
    std::vector<cell::EpisodeRecord>& records = collected.records;
    EpisodeDriver driver(vec_env, policy, 7);
    driver.AddSink(collected.recorder);
    if (lock_step) driver.RequireLockStep();
    ASSERT_EQ(driver.schedule(), lock_step ? EpisodeDriver::Schedule::kLockStep : EpisodeDriver::Schedule::kPerSlot);
    driver.Run();
    ASSERT_EQ(records.size(), 7u);
    for (const cell::EpisodeRecord& record : records) {
      const bool odd = record.episode % 2 == 1;
      EXPECT_EQ(record.end, odd ? engine::EpisodeEnd::kGaveUp : engine::EpisodeEnd::kTimeOut)
          << "episode " << record.episode << (lock_step ? " lock-step" : " per slot");
      EXPECT_EQ(record.length_control_ticks, odd ? 7 : 15) << "episode " << record.episode;
      EXPECT_FALSE(record.success);
    }
    EXPECT_EQ(driver.control_ticks(), 4 * 15 + 3 * 7);
  }
}

// ood-init-pose resets (30 warm-up ticks each) run in parallel: the episodes' end states do not
// depend on the number of slots or threads.
std::vector<std::vector<double>> WarmUpEndStates(int slots, std::size_t threads) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  VecEnv vec_env(Model("clutter-pick-cube", 0.75), scenarios::FindScenario("clutter-pick-cube"),
                 scenarios::Split::kOodInitPose, slots, 9);
  std::unique_ptr<Policy> hold = MakeBuiltinPolicy("hold", vec_env.scenario(), vec_env.model(), slots);
  EventLog log;
  EpisodeDriver driver(vec_env, *hold, 5);
  driver.AddSink(log);
  driver.Run();
  std::vector<std::vector<double>> by_episode(5);
  std::size_t next = 0;
  for (const Event& event : log.events) {
    if (event.kind == 'E') by_episode[static_cast<std::size_t>(event.episode)] = log.final_q[next++];
  }
  return by_episode;
}

TEST(EpisodeDriver, ParallelResetsWithWarmUpGiveTheSameEpisodesForAnySlotsAndThreads) {
  const auto serial = WarmUpEndStates(1, 1);
  for (const auto& q : serial) ASSERT_FALSE(q.empty());
  EXPECT_EQ(WarmUpEndStates(4, 2), serial);
  EXPECT_EQ(WarmUpEndStates(5, 1), serial);
}

// What the per-slot schedule's sinks see: per-slot tick counts (touched only by their slot's
// thread) and the ends, which come one at a time. Optionally stops each episode after a number
// of ticks, or throws at an end.
class PerSlotLog : public EpisodeSink {
 public:
  PerSlotLog(int slots, int stop_after_ticks, int throw_at_end = -1)
      : ticks_(static_cast<std::size_t>(slots), 0), stop_after_ticks_(stop_after_ticks), throw_at_end_(throw_at_end) {}
  void EpisodeStarted(const VecEnv&, int slot) override { ticks_[static_cast<std::size_t>(slot)] = 0; }
  void ActionChosen(const VecEnv&, int slot, const kinematics::Action&) override {
    ++ticks_[static_cast<std::size_t>(slot)];
  }
  bool EpisodeComplete(const VecEnv& vec_env, int slot) const override {
    return stop_after_ticks_ >= 0 && vec_env.state().control_step[slot] >= stop_after_ticks_;
  }
  void EpisodeEnded(const VecEnv& vec_env, int slot) override {
    if (static_cast<int>(ended.size()) == throw_at_end_) throw std::runtime_error("disk full");
    ended.push_back(
        {'E', slot, vec_env.state().episode[slot], vec_env.state().end[slot], vec_env.state().control_step[slot]});
    action_ticks += ticks_[static_cast<std::size_t>(slot)];
  }
  bool works_per_slot() const override { return true; }

  std::vector<Event> ended;
  int64_t action_ticks = 0;

 private:
  std::vector<int64_t> ticks_;
  int stop_after_ticks_;
  int throw_at_end_;
};

engine::WorldModel TaskModel(const std::string& task) {
  const kinematics::RobotModel robot = tavis::testing::LoadRobot("gr1t2");
  return BuildWorldModel(robot, scenarios::FindScenario(task));
}

TEST(EpisodeDriver, RunsPerSlotOnlyWhenPolicyCamerasAndEverySinkAllowIt) {
  VecEnv vec_env(Model("clutter-pick-cube", 0.25), scenarios::FindScenario("clutter-pick-cube"), scenarios::Split::kId,
                 2, 1);
  std::unique_ptr<Policy> hold = MakeBuiltinPolicy("hold", vec_env.scenario(), vec_env.model(), 2);
  PerSlotLog per_slot(2, -1);
  EventLog lock_step;
  {
    EpisodeDriver driver(vec_env, *hold, 1);
    driver.AddSink(per_slot);
    EXPECT_EQ(driver.schedule(), EpisodeDriver::Schedule::kPerSlot);
    driver.AddSink(lock_step);
    EXPECT_EQ(driver.schedule(), EpisodeDriver::Schedule::kLockStep) << "a sink that needs the common tick";
  }
  {
    EpisodeDriver driver(vec_env, *hold, 1);
    driver.RequireLockStep();
    EXPECT_EQ(driver.schedule(), EpisodeDriver::Schedule::kLockStep);
  }
  {
    CheckingPolicy batched(vec_env);
    EpisodeDriver driver(vec_env, batched, 1);
    EXPECT_EQ(driver.schedule(), EpisodeDriver::Schedule::kLockStep) << "a policy answering the whole batch";
  }
  vec_env.EnableCameras({{"head"}, 32, 24});
  EpisodeDriver driver(vec_env, *hold, 1);
  EXPECT_EQ(driver.schedule(), EpisodeDriver::Schedule::kPerSlot) << "each slot renders at its own policy ticks";
}

// Every image a policy is given: per episode, at each of its policy ticks, a hash of each
// camera's pixels, taken when the driver hands the tick's action over (the images are rendered
// for that tick by then, on either schedule).
class ImageLog : public EpisodeSink {
 public:
  explicit ImageLog(int slots) : running_(static_cast<std::size_t>(slots)) {}
  void EpisodeStarted(const VecEnv&, int slot) override { running_[static_cast<std::size_t>(slot)].clear(); }
  void ActionChosen(const VecEnv& vec_env, int slot, const kinematics::Action&) override {
    const engine::BatchState& state = vec_env.state();
    if (state.control_step[slot] % vec_env.model().physics.controls_per_policy() != 0) return;
    const render::ImageBatch& images = *vec_env.images();
    for (int camera = 0; camera < images.n_cameras(); ++camera) {
      const uint8_t* rgb = images.rgb(slot, camera);
      const std::size_t size =
          static_cast<std::size_t>(images.width(camera)) * static_cast<std::size_t>(images.height(camera)) * 3;
      uint64_t hash = 1469598103934665603ull;  // FNV-1a
      for (std::size_t i = 0; i < size; ++i) hash = (hash ^ rgb[i]) * 1099511628211ull;
      running_[static_cast<std::size_t>(slot)].push_back(hash);
      lit_pixels += static_cast<int64_t>(std::count_if(rgb, rgb + size, [](uint8_t value) { return value != 0; }));
    }
  }
  void EpisodeEnded(const VecEnv& vec_env, int slot) override {
    by_episode[vec_env.state().episode[slot]] = std::move(running_[static_cast<std::size_t>(slot)]);
  }
  bool works_per_slot() const override { return true; }

  std::map<int64_t, std::vector<uint64_t>> by_episode;
  std::atomic<int64_t> lit_pixels{0};

 private:
  std::vector<std::vector<uint64_t>> running_;  // [slot] the running episode's hashes
};

struct RenderedRun {
  std::vector<cell::EpisodeRecord> records;
  std::map<int64_t, std::vector<uint64_t>> images;
  int64_t lit_pixels = 0;
  int64_t rendered_images = 0;
  cell::CellProfile profile;
};

// The expert on clutter-pick-cube with the head and left wrist cameras rendered at every policy
// tick, as `tavis eval --render-cameras` runs it.
RenderedRun RenderedExpert(bool lock_step, std::size_t threads, int slots) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  VecEnv vec_env(TaskModel("clutter-pick-cube"), scenarios::FindScenario("clutter-pick-cube"), scenarios::Split::kId,
                 slots, 5);
  vec_env.EnableCameras({{"head", "left_wrist"}, 32, 24});
  std::unique_ptr<Policy> expert = MakeBuiltinPolicy("expert", vec_env.scenario(), vec_env.model(), slots);
  cell::RecordSettings settings;
  settings.galt_stride = 1;
  settings.galt_fps = vec_env.model().physics.control_hz;
  settings.keep_actions = true;
  RecordCollector collected(vec_env, settings);
  ImageLog images(slots);
  EpisodeDriver driver(vec_env, *expert, 4);
  driver.AddSink(images);
  driver.AddSink(collected.recorder);
  if (lock_step) driver.RequireLockStep();
  EXPECT_EQ(driver.schedule(), lock_step ? EpisodeDriver::Schedule::kLockStep : EpisodeDriver::Schedule::kPerSlot);
  cell::CellProfiler profiler;
  driver.SetObserver(profiler);
  driver.Run();
  return {collected.records, images.by_episode, images.lit_pixels.load(), vec_env.rendered_images(),
          profiler.profile()};
}

double Stage(const cell::CellProfile& profile, const std::string& name) {
  for (const auto& [stage, seconds] : profile.stages) {
    if (stage == name) return seconds;
  }
  ADD_FAILURE() << "no stage " << name;
  return 0.0;
}

// --profile's render figures: the CPU time inside render calls and the thread time they held
// idle. Per slot a render is part of its episode's cost (so not counted again for the
// estimates); lock-step a render call holds every thread the run may use (`--threads`, not the
// machine's cores).
TEST(EpisodeDriver, TheProfileReportsRenderCpuAndIdleTimeOnEitherScheduleAndThreadCount) {
  for (const std::size_t threads : {std::size_t{1}, std::size_t{2}}) {
    for (const bool lock_step : {false, true}) {
      const RenderedRun run = RenderedExpert(lock_step, threads, 3);
      const cell::CellProfile& profile = run.profile;
      const std::string label = std::string(lock_step ? "lock-step" : "per slot") + " on " + std::to_string(threads);
      const int usable = std::min(static_cast<int>(threads), tbb::this_task_arena::max_concurrency());
      EXPECT_EQ(profile.threads, usable) << label;
      EXPECT_GT(profile.render_cpu_seconds, 0.0) << label;
      EXPECT_GT(profile.render_wall_seconds, 0.0) << label;
      EXPECT_GE(profile.render_idle_seconds, 0.0) << label;
      EXPECT_DOUBLE_EQ(Stage(profile, "render"), profile.render_cpu_seconds) << label;
      if (lock_step) {
        EXPECT_DOUBLE_EQ(Stage(profile, "render_idle"), profile.render_idle_seconds);
        // Each batch call holds the run's threads for its wall time: what they did not spend
        // rendering is idle.
        EXPECT_NEAR(profile.render_seconds, usable * profile.render_wall_seconds, 1e-6) << label;
        EXPECT_NEAR(profile.render_cpu_seconds + profile.render_idle_seconds, profile.render_seconds,
                    1e-3 * profile.render_seconds);
      } else {
        EXPECT_EQ(profile.render_seconds, 0.0) << "per slot, renders are in the episodes' costs";
        for (const auto& stage : profile.stages) EXPECT_NE(stage.first, "render_idle") << "preemption is no work";
        double episode_costs = 0.0;
        for (const cell::EpisodeCost& cost : profile.episodes) episode_costs += cost.seconds;
        EXPECT_GT(episode_costs, profile.render_cpu_seconds);
        EXPECT_NEAR(profile.render_cpu_seconds + profile.render_idle_seconds, profile.render_wall_seconds,
                    1e-3 * profile.render_wall_seconds);
      }
    }
  }
}

TEST(EpisodeDriver, ARenderedExpertCellGivesTheSameRecordsAndImagesOnEitherScheduleAndThreadCount) {
  const RenderedRun lock_step = RenderedExpert(true, 2, 3);
  ASSERT_EQ(lock_step.records.size(), 4u);
  ASSERT_EQ(lock_step.images.size(), 4u);
  EXPECT_GT(lock_step.lit_pixels, 0) << "the cameras see the scene";
  int64_t policy_ticks = 0;
  for (const cell::EpisodeRecord& record : lock_step.records) {
    const auto& hashes = lock_step.images.at(record.episode);
    EXPECT_EQ(hashes.size(), 2u * static_cast<std::size_t>(record.length_steps)) << "two cameras at every policy tick";
    policy_ticks += static_cast<int64_t>(hashes.size()) / 2;
  }
  struct Variant {
    bool lock_step;
    std::size_t threads;
    int slots;
  };
  for (const Variant& variant :
       {Variant{false, 1, 3}, Variant{false, 2, 3}, Variant{false, 2, 2}, Variant{true, 1, 4}}) {
    const RenderedRun run = RenderedExpert(variant.lock_step, variant.threads, variant.slots);
    const std::string label = std::string(variant.lock_step ? "lock-step" : "per slot") + ", " +
                              std::to_string(variant.threads) + " threads, " + std::to_string(variant.slots) + " slots";
    ASSERT_EQ(run.records.size(), lock_step.records.size()) << label;
    for (std::size_t i = 0; i < run.records.size(); ++i) {
      const cell::EpisodeRecord& a = lock_step.records[i];
      const cell::EpisodeRecord& b = run.records[i];
      EXPECT_EQ(b.episode, a.episode) << label;
      EXPECT_EQ(b.end, a.end) << label << ", episode " << a.episode;
      EXPECT_EQ(b.length_control_ticks, a.length_control_ticks) << label << ", episode " << a.episode;
      EXPECT_EQ(b.actions, a.actions) << label << ", episode " << a.episode;
    }
    EXPECT_EQ(run.images, lock_step.images) << label << ": every policy tick's images";
    EXPECT_EQ(run.rendered_images, 2 * policy_ticks) << label << ": each env-camera image is rendered once";
  }
}

TEST(EpisodeDriver, PerSlotScheduleRunsEveryEpisodeOnceAndStopsThoseASinkIsDoneWith) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
  VecEnv vec_env(Model("clutter-pick-cube", 0.25), scenarios::FindScenario("clutter-pick-cube"), scenarios::Split::kId,
                 3, 1);
  std::unique_ptr<Policy> hold = MakeBuiltinPolicy("hold", vec_env.scenario(), vec_env.model(), 3);
  PerSlotLog log(3, /*stop_after_ticks=*/5);
  EpisodeDriver driver(vec_env, *hold, 7, /*first_episode=*/2);
  driver.AddSink(log);
  std::vector<int64_t> progress;
  driver.SetProgress([&](int64_t finished, int64_t total) {
    EXPECT_EQ(total, 7);
    progress.push_back(finished);
  });
  ASSERT_EQ(driver.schedule(), EpisodeDriver::Schedule::kPerSlot);
  driver.Run();
  EXPECT_EQ(progress, (std::vector<int64_t>{0, 1, 2, 3, 4, 5, 6, 7}));
  std::vector<int64_t> episodes;
  for (const Event& event : log.ended) {
    episodes.push_back(event.episode);
    EXPECT_EQ(event.end, engine::EpisodeEnd::kStopped);
    EXPECT_EQ(event.control_step, 5);
    EXPECT_LT(event.slot, 2) << "one slot per thread";
  }
  std::sort(episodes.begin(), episodes.end());
  EXPECT_EQ(episodes, (std::vector<int64_t>{2, 3, 4, 5, 6, 7, 8}));
  EXPECT_EQ(driver.control_ticks(), 7 * 5);
  EXPECT_EQ(log.action_ticks, 7 * 5);
  for (int slot = 0; slot < 3; ++slot) EXPECT_EQ(vec_env.state().episode[slot], -1) << "slots are released at the end";
}

// The expert's records (outcome, length, GALT, every tick's action) of a few clutter-pick-cube
// episodes, on either schedule and thread count.
std::vector<cell::EpisodeRecord> ExpertRecords(bool lock_step, std::size_t threads) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  VecEnv vec_env(TaskModel("clutter-pick-cube"), scenarios::FindScenario("clutter-pick-cube"), scenarios::Split::kId, 3,
                 5);
  std::unique_ptr<Policy> expert = MakeBuiltinPolicy("expert", vec_env.scenario(), vec_env.model(), 3);
  cell::RecordSettings settings;
  settings.galt_stride = 1;
  settings.galt_fps = vec_env.model().physics.control_hz;
  settings.keep_actions = true;
  RecordCollector collected(vec_env, settings);
  std::vector<cell::EpisodeRecord>& records = collected.records;
  EpisodeDriver driver(vec_env, *expert, 5);
  driver.AddSink(collected.recorder);
  if (lock_step) driver.RequireLockStep();
  EXPECT_EQ(driver.schedule(), lock_step ? EpisodeDriver::Schedule::kLockStep : EpisodeDriver::Schedule::kPerSlot);
  driver.Run();
  return records;
}

TEST(EpisodeDriver, PerSlotScheduleRecordsExactlyWhatLockStepRecords) {
  const std::vector<cell::EpisodeRecord> lock_step = ExpertRecords(true, 2);
  ASSERT_EQ(lock_step.size(), 5u);
  int successes = 0;
  for (const cell::EpisodeRecord& record : lock_step) successes += record.success ? 1 : 0;
  EXPECT_GE(successes, 4) << "the expert solves the task";
  for (std::size_t threads : {1, 2}) {
    const std::vector<cell::EpisodeRecord> per_slot = ExpertRecords(false, threads);
    ASSERT_EQ(per_slot.size(), lock_step.size());
    for (std::size_t i = 0; i < lock_step.size(); ++i) {
      EXPECT_EQ(per_slot[i].episode, lock_step[i].episode) << "records in episode order";
      EXPECT_EQ(per_slot[i].end, lock_step[i].end);
      EXPECT_EQ(per_slot[i].length_control_ticks, lock_step[i].length_control_ticks);
      EXPECT_EQ(per_slot[i].actions, lock_step[i].actions) << "episode " << i << " on " << threads << " threads";
      ASSERT_EQ(per_slot[i].galt.has_value(), lock_step[i].galt.has_value());
      if (per_slot[i].galt) {
        EXPECT_EQ(per_slot[i].galt->galt_s, lock_step[i].galt->galt_s);
      }
    }
  }
}

TEST(EpisodeDriver, ASinkFailingOnThePerSlotScheduleStopsTheRunEarly) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
  VecEnv vec_env(Model("clutter-pick-cube", 0.25), scenarios::FindScenario("clutter-pick-cube"), scenarios::Split::kId,
                 2, 1);
  std::unique_ptr<Policy> hold = MakeBuiltinPolicy("hold", vec_env.scenario(), vec_env.model(), 2);
  PerSlotLog log(2, -1, /*throw_at_end=*/1);
  EpisodeDriver driver(vec_env, *hold, 40);
  driver.AddSink(log);
  int64_t finished = 0;
  driver.SetProgress([&](int64_t done, int64_t) { finished = done; });
  EXPECT_THROW(driver.Run(), std::runtime_error);
  EXPECT_EQ(log.ended.size(), 1u);
  EXPECT_LT(finished, 40) << "the other thread stops at its next deal";
}

// With cameras, a lock-step batch stays in phase: episodes stopped after 4 to 6 ticks are
// followed by episodes that start on the batch's next policy tick, so every render call draws
// all running envs.
class PhaseLog : public EpisodeSink {
 public:
  void TickStarting(const VecEnv& vec_env) override {
    const engine::BatchState& state = vec_env.state();
    int phase = -1;
    for (int slot = 0; slot < state.num_envs; ++slot) {
      if (!state.running(slot)) continue;
      const int slot_phase = state.control_step[slot] % vec_env.model().physics.controls_per_policy();
      if (phase >= 0 && slot_phase != phase) ++out_of_phase_ticks;
      phase = slot_phase;
    }
  }
  // Episode i stops after 4 + i % 3 ticks: without alignment the slots would drift apart.
  bool EpisodeComplete(const VecEnv& vec_env, int slot) const override {
    return vec_env.state().control_step[slot] >= 4 + vec_env.state().episode[slot] % 3;
  }
  void EpisodeEnded(const VecEnv&, int) override { ++ended; }

  int out_of_phase_ticks = 0;
  int ended = 0;
};

TEST(EpisodeDriver, WithCamerasEpisodesStartOnTheBatchsPolicyTicks) {
  VecEnv vec_env(Model("clutter-pick-cube", 0.25), scenarios::FindScenario("clutter-pick-cube"), scenarios::Split::kId,
                 3, 1);
  vec_env.EnableCameras({{"head"}, 32, 24});
  std::unique_ptr<Policy> hold = MakeBuiltinPolicy("hold", vec_env.scenario(), vec_env.model(), 3);
  PhaseLog log;
  EpisodeDriver driver(vec_env, *hold, 8);
  driver.AddSink(log);
  driver.Run();
  EXPECT_EQ(log.ended, 8);
  EXPECT_EQ(log.out_of_phase_ticks, 0);
  EXPECT_EQ(driver.control_ticks(), 3 * 4 + 3 * 5 + 2 * 6);
}

// Every hook the loop gives its observer, checked as it comes: a part opens and closes before
// the next of its slot opens, an episode's end is told between EpisodeEnding and EpisodeEnded, one
// end at a time.
class HookLog : public LoopObserver {
 public:
  void RunStarting(VecEnv& vec_env, Policy&, bool per_slot) override {
    std::lock_guard<std::mutex> lock(mutex_);
    ++runs;
    run_per_slot = per_slot;
    open_.assign(static_cast<std::size_t>(vec_env.num_envs()) + 1, -1);
  }
  void RunEnded() override { ++runs_ended; }
  void PartStarting(LoopPart part, int slot) override {
    std::lock_guard<std::mutex> lock(mutex_);
    EXPECT_EQ(open_[static_cast<std::size_t>(slot + 1)], -1) << "a part of slot " << slot << " still open";
    open_[static_cast<std::size_t>(slot + 1)] = static_cast<int>(part);
    ++parts[{part, slot >= 0}];
  }
  void PartEnded(LoopPart part, int slot) override {
    std::lock_guard<std::mutex> lock(mutex_);
    EXPECT_EQ(open_[static_cast<std::size_t>(slot + 1)], static_cast<int>(part));
    open_[static_cast<std::size_t>(slot + 1)] = -1;
  }
  void EpisodesStarting(const std::vector<uint8_t>& starting) override {
    EXPECT_EQ(open_[0], -1) << "the batch's starts are told before its reset";
    starting_ = starting;
  }
  void EpisodesStarted(const std::vector<uint8_t>& started) override {
    EXPECT_EQ(started, starting_) << "the slots told as starting are those started";
    for (uint8_t flag : started) batch_starts += flag;
  }
  void TickEnded() override { ++ticks; }
  void EnvReset(int) override { ++env_resets; }
  void EpisodeEnding(int slot) override {
    EXPECT_EQ(ending_, -1) << "one end at a time";
    ending_ = slot;
  }
  void EpisodeEnded(int slot) override {
    EXPECT_EQ(ending_, slot);
    ending_ = -1;
    ++ends;
  }
  int Parts(LoopPart part, bool of_a_slot) const {
    const auto found = parts.find({part, of_a_slot});
    return found == parts.end() ? 0 : found->second;
  }

  int runs = 0, runs_ended = 0, ticks = 0, batch_starts = 0, ends = 0;
  bool run_per_slot = false;
  std::atomic<int> env_resets{0};
  std::map<std::pair<LoopPart, bool>, int> parts;  // (part, of a slot rather than the batch)

 private:
  std::mutex mutex_;
  std::vector<int> open_;  // [slot + 1] the open part, -1 if none
  std::vector<uint8_t> starting_;
  int ending_ = -1;
};

TEST(EpisodeDriver, TellsItsObserverOfEveryPartAndEpisodeOnEitherSchedule) {
  for (const bool lock_step : {true, false}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    VecEnv vec_env(Model("clutter-pick-cube", 0.25), scenarios::FindScenario("clutter-pick-cube"),
                   scenarios::Split::kId, 2, 1);
    std::unique_ptr<Policy> hold = MakeBuiltinPolicy("hold", vec_env.scenario(), vec_env.model(), 2);
    RecordCollector collected(vec_env);
    HookLog hooks;
    EpisodeDriver driver(vec_env, *hold, 5);
    driver.AddSink(collected.recorder);
    driver.SetObserver(hooks);
    if (lock_step) driver.RequireLockStep();
    driver.Run();
    const std::string label = lock_step ? "lock-step" : "per slot";
    EXPECT_EQ(collected.records.size(), 5u) << label;
    EXPECT_EQ(hooks.runs, 1) << label;
    EXPECT_EQ(hooks.runs_ended, 1) << label;
    EXPECT_EQ(hooks.run_per_slot, !lock_step) << label;
    EXPECT_EQ(hooks.ends, 5) << label;
    if (lock_step) {
      // Three rounds of 15 ticks (episodes 0-1, 2-3, 4), each tick one policy part.
      EXPECT_EQ(hooks.ticks, 45);
      EXPECT_EQ(hooks.Parts(LoopPart::kPolicyActs, false), 45);
      EXPECT_EQ(hooks.batch_starts, 5);
      EXPECT_EQ(hooks.env_resets, 0);
      // Per refill: the env's reset and the policy's; per tick: the render and the step.
      EXPECT_EQ(hooks.Parts(LoopPart::kReset, false), 3);
      EXPECT_EQ(hooks.Parts(LoopPart::kPolicyResets, false), 3);
      EXPECT_EQ(hooks.Parts(LoopPart::kRender, false), 45);
      EXPECT_EQ(hooks.Parts(LoopPart::kStep, false), 45);
      EXPECT_EQ(hooks.Parts(LoopPart::kParallel, false), 0);
      EXPECT_EQ(hooks.Parts(LoopPart::kStep, true), 0);
      // Per refill: EpisodeStarted; per tick: TickStarting, ActionChosen and Stepped.
      EXPECT_EQ(hooks.Parts(LoopPart::kSinks, false), 3 + 45 * 3);
      EXPECT_EQ(hooks.Parts(LoopPart::kSinks, true), 0);
    } else {
      EXPECT_EQ(hooks.ticks, 0);
      EXPECT_EQ(hooks.batch_starts, 0);
      EXPECT_EQ(hooks.env_resets, 5);
      EXPECT_EQ(hooks.Parts(LoopPart::kParallel, false), 1) << "the workers";
      EXPECT_EQ(hooks.Parts(LoopPart::kPolicyActs, false), 0);
      // Per episode: its env's reset and the policy's; per tick the step, and at each of the
      // hold's actions (every third tick, the policy rate) its part (no cameras: no render part).
      EXPECT_EQ(hooks.Parts(LoopPart::kReset, true), 5);
      EXPECT_EQ(hooks.Parts(LoopPart::kPolicyResets, true), 5);
      EXPECT_EQ(hooks.Parts(LoopPart::kPolicyActs, true), 5 * 5);
      EXPECT_EQ(hooks.Parts(LoopPart::kStep, true), 5 * 15);
      EXPECT_EQ(hooks.Parts(LoopPart::kRender, true), 0);
      // Per episode: EpisodeStarted; per tick: SlotTickStarting, ActionChosen and SlotStepped.
      EXPECT_EQ(hooks.Parts(LoopPart::kSinks, true), 5 * (1 + 15 * 3));
      EXPECT_EQ(hooks.Parts(LoopPart::kSinks, false), 0);
    }
  }
}

}  // namespace
}  // namespace tavis::batch

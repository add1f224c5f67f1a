// Stage metrics (scenarios/stage.h): what the scripted expert, the hold policy and a policy that
// goes for the wrong side reach, and how records carry stages and targets through episodes.jsonl.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/builtin_policies.h"
#include "batch/cell/cell_record_stream.h"
#include "batch/cell/cell_report.h"
#include "batch/cell/episode_recorder.h"
#include "batch/cell/stage_record.h"
#include "batch/episode_driver.h"
#include "scenarios/registry.h"
#include "tests/support/robot_loading.h"
#include "tests/support/wrong_side_policy.h"

namespace tavis::batch::cell {
namespace {

VecEnv MakeEnv(const std::string& task, double episode_length_s, int envs) {
  const scenarios::ScenarioDef& scenario = scenarios::FindScenario(task);
  const kinematics::RobotModel robot = tavis::testing::LoadRobot("gr1t2");
  engine::WorldModel model = BuildWorldModel(robot, scenario);
  model.physics.episode_length_s = episode_length_s;
  return VecEnv(std::move(model), scenario, scenarios::Split::kId, envs, 5);
}

// Per episode, at its start: the target's y and each enabled dynamic object's start height; and
// over the episode, each object's highest z.
class ObjectWatch : public EpisodeSink {
 public:
  void EpisodeStarted(const VecEnv& vec_env, int slot) override {
    const engine::BatchState& state = vec_env.state();
    target_y.push_back(state.ObjectPosition(slot, state.target(slot)).y());
    target_name.push_back(vec_env.model().objects[static_cast<std::size_t>(state.target(slot))].name);
    start_z.emplace_back();
    for (int object = 0; object < state.num_objects; ++object)
      start_z.back().push_back(state.ObjectPosition(slot, object).z());
    highest_z.push_back(start_z.back());
    slot_episode_.resize(static_cast<std::size_t>(vec_env.num_envs()));
    slot_episode_[static_cast<std::size_t>(slot)] = highest_z.size() - 1;
  }
  void Stepped(const VecEnv& vec_env) override {
    const engine::BatchState& state = vec_env.state();
    for (int slot = 0; slot < vec_env.num_envs(); ++slot) {
      if (!state.running(slot)) continue;
      std::vector<double>& highest = highest_z[slot_episode_[static_cast<std::size_t>(slot)]];
      for (int object = 0; object < state.num_objects; ++object) {
        highest[static_cast<std::size_t>(object)] =
            std::max(highest[static_cast<std::size_t>(object)], state.ObjectPosition(slot, object).z());
      }
    }
  }
  std::vector<double> target_y;  // in start order
  std::vector<std::string> target_name;
  std::vector<std::vector<double>> start_z;    // [episode in start order][object]
  std::vector<std::vector<double>> highest_z;  // the same, the highest seen

 private:
  std::vector<std::size_t> slot_episode_;
};

struct CellRun {
  std::vector<EpisodeRecord> records;  // in episode order
  ObjectWatch watch;
};

// `episodes` episodes of `policy` on the lock-step schedule, recorded and watched.
CellRun RunCell(VecEnv& vec_env, Policy& policy, int episodes) {
  CellRun run;
  EpisodeRecorder recorder(vec_env.num_envs(), vec_env.model().physics.max_control_steps(), RecordSettings(), 0,
                           [&run](EpisodeRecord&& record) { run.records.push_back(std::move(record)); });
  EpisodeDriver driver(vec_env, policy, episodes);
  driver.AddSink(recorder);
  driver.AddSink(run.watch);
  driver.RequireLockStep();
  driver.Run();
  return run;
}

// The same for a built-in policy ("expert", "hold").
CellRun RunBuiltinCell(VecEnv& vec_env, const std::string& policy, int episodes) {
  const std::unique_ptr<Policy> builtin =
      MakeBuiltinPolicy(policy, vec_env.scenario(), vec_env.model(), vec_env.num_envs());
  return RunCell(vec_env, *builtin, episodes);
}

const StageReached& Stage(const EpisodeRecord& record, const std::string& name) {
  for (const StageReached& stage : record.stages) {
    if (stage.name == name) return stage;
  }
  throw std::runtime_error("episode " + std::to_string(record.episode) + " has no stage " + name);
}

TEST(StageMetrics, ConditionalPickDeclaresTheCueThenThePickStages) {
  std::vector<std::string> names;
  for (const scenarios::StageDef& stage : scenarios::FindScenario("conditional-pick").stages)
    names.push_back(stage.name);
  EXPECT_EQ(names, (std::vector<std::string>{"cue_fixated", "target_approached", "target_grasped", "target_lifted"}));
  EXPECT_EQ(StageNames("multi-shelf-scan"),
            (std::vector<std::string>{"target_approached", "target_grasped", "target_pulled"}));
}

TEST(StageMetrics, TheExpertPassesEveryStageInOrderAndRecordsItsTarget) {
  VecEnv vec_env = MakeEnv("conditional-pick", 12.0, 3);
  const CellRun run = RunBuiltinCell(vec_env, "expert", 3);
  ASSERT_EQ(run.records.size(), 3u);
  for (const EpisodeRecord& record : run.records) {
    SCOPED_TRACE("episode " + std::to_string(record.episode));
    EXPECT_TRUE(record.success);
    ASSERT_EQ(record.stages.size(), 4u);
    int previous = 0;
    for (const StageReached& stage : record.stages) {
      EXPECT_TRUE(stage.reached()) << stage.name;
      EXPECT_GE(stage.first_tick, previous) << stage.name << " comes after the stage before it";
      EXPECT_LE(stage.first_tick, record.length_control_ticks) << stage.name;
      previous = stage.first_tick;
    }
    EXPECT_GT(Stage(record, "target_grasped").first_tick, Stage(record, "target_approached").first_tick);
    EXPECT_EQ(record.prompt, scenarios::FindScenario("conditional-pick").prompt(vec_env.state(), 0));
  }
  // The recorded side is where the target stood: the robot's left is +y.
  ASSERT_EQ(run.watch.target_y.size(), 3u);
  std::vector<std::string> sides, objects;
  for (const EpisodeRecord& record : run.records) {
    ASSERT_EQ(record.target.size(), 1u) << "conditional-pick's one fact: the target's side";
    EXPECT_EQ(record.target[0].key, "side");
    sides.push_back(std::get<std::string>(record.target[0].value));
    objects.push_back(record.target_object);
  }
  std::vector<std::string> expected;
  // Episodes start in index order on the lock-step schedule.
  for (double y : run.watch.target_y) expected.push_back(y > 0.0 ? "left" : "right");
  EXPECT_EQ(sides, expected);
  EXPECT_EQ(objects, run.watch.target_name);
}

TEST(StageMetrics, TheHoldPolicyNeverGrasps) {
  VecEnv vec_env = MakeEnv("clutter-pick-cube", 3.0, 2);
  const CellRun run = RunBuiltinCell(vec_env, "hold", 2);
  ASSERT_EQ(run.records.size(), 2u);
  for (const EpisodeRecord& record : run.records) {
    EXPECT_FALSE(Stage(record, "target_grasped").reached());
    EXPECT_FALSE(Stage(record, "target_lifted").reached());
  }
  EXPECT_EQ(StageFunnel(FunnelStages("clutter-pick-cube", CameraProtocol::kHead), run.records)[1].reached, 0);
}

TEST(StageMetrics, APolicyThatPicksTheWrongSideFailsAtTheCorrectTarget) {
  VecEnv vec_env = MakeEnv("conditional-pick", 10.0, 3);
  testing::WrongSidePolicy wrong_side(vec_env);
  const CellRun run = RunCell(vec_env, wrong_side, 3);
  ASSERT_EQ(run.records.size(), 3u);
  int lifted_the_other = 0;
  for (std::size_t i = 0; i < run.records.size(); ++i) {
    const EpisodeRecord& record = run.records[i];
    SCOPED_TRACE("episode " + std::to_string(record.episode));
    EXPECT_FALSE(record.success);
    EXPECT_TRUE(Stage(record, "cue_fixated").reached()) << "it looked at the card";
    EXPECT_FALSE(Stage(record, "target_approached").reached());
    EXPECT_FALSE(Stage(record, "target_grasped").reached());
    // It did pick something: an object other than the target rose 5 cm.
    const std::vector<double>& start = run.watch.start_z[i];
    const std::vector<double>& highest = run.watch.highest_z[i];
    for (std::size_t object = 0; object < start.size(); ++object) {
      if (highest[object] > start[object] + 0.05) ++lifted_the_other;
    }
  }
  EXPECT_EQ(lifted_the_other, 3) << "one wrong object lifted per episode";
  const std::vector<FunnelStep> funnel =
      StageFunnel(FunnelStages("conditional-pick", CameraProtocol::kHead), run.records);
  EXPECT_EQ(funnel[0].reached, 3);
  EXPECT_EQ(funnel[1].reached, 0);
}

TEST(StageMetrics, RecordsCarryStagesAndTargetsThroughTheirJsonLine) {
  EpisodeRecord record;
  record.episode = 4;
  record.end = engine::EpisodeEnd::kTimeOut;
  record.prompt = "Find the red cube and pick it up.";
  record.target_object = "red_cube";
  record.target = {{"shelf", 2}};
  record.stages = {{"target_approached", 120}, {"target_grasped", 300}, {"target_lifted", -1}};
  const std::string text = EpisodeJsonLine(record, 9);
  const nlohmann::json line = nlohmann::json::parse(text);
  EXPECT_EQ(line.at("stages"),
            nlohmann::json({{"target_approached", true}, {"target_grasped", true}, {"target_lifted", false}}));
  EXPECT_EQ(line.at("stage_ticks").at("target_grasped"), 300);
  EXPECT_TRUE(line.at("stage_ticks").at("target_lifted").is_null());
  EXPECT_EQ(line.at("target"), nlohmann::json({{"object", "red_cube"}, {"shelf", 2}}));
  const EpisodeRecord back = ParseEpisodeJsonLine(text);
  EXPECT_EQ(back.prompt, record.prompt);
  EXPECT_EQ(back.target_object, "red_cube");
  EXPECT_EQ(back.target, record.target);
  for (const StageReached& stage : record.stages) EXPECT_EQ(Stage(back, stage.name), stage);
  EXPECT_EQ(EpisodeJsonLine(back, 9), text) << "a resumed record writes the same line";

  // A line from before stages existed reads back with none.
  const EpisodeRecord old = ParseEpisodeJsonLine(
      R"({"end":"time_out","episode":0,"length_control_ticks":1200,"length_steps":400,"seed":0,"solver_messages":0,"success":false})");
  EXPECT_TRUE(old.stages.empty());
  EXPECT_THROW(
      ParseEpisodeJsonLine(
          R"({"end":"time_out","episode":0,"length_control_ticks":1,"length_steps":1,"seed":0,"solver_messages":0,"success":false,"stage_ticks":{"target_grasped":"soon"}})"),
      std::invalid_argument);
}

// A task's facts are its own keys and values: the record writes and reads whatever a task
// declares, text or whole number, and refuses another kind of value naming its key.
TEST(StageMetrics, ATasksOwnFactsGoThroughTheJsonLineByTheirKeys) {
  EpisodeRecord record;
  record.episode = 1;
  record.end = engine::EpisodeEnd::kSuccess;
  record.target_object = "soup_can";
  record.target = {{"lane", "middle"}, {"row", 3}};
  record.target_move_tick = 40;
  const std::string text = EpisodeJsonLine(record, 2);
  const nlohmann::json line = nlohmann::json::parse(text);
  EXPECT_EQ(line.at("target"),
            nlohmann::json({{"object", "soup_can"}, {"lane", "middle"}, {"row", 3}, {"moved_tick", 40}}));
  const EpisodeRecord back = ParseEpisodeJsonLine(text);
  EXPECT_EQ(back.target, (scenarios::TargetFacts{{"lane", "middle"}, {"row", 3}}));
  EXPECT_EQ(back.target_move_tick, 40);
  EXPECT_EQ(EpisodeJsonLine(back, 2), text);
  try {
    ParseEpisodeJsonLine(R"({"end":"success","episode":0,"length_control_ticks":1,"length_steps":1,"seed":0,)"
                         R"("solver_messages":0,"success":true,"target":{"object":"soup_can","lane":2.5}})");
    ADD_FAILURE() << "a fact that is neither text nor a whole number is refused";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("target.lane 2.5"), std::string::npos) << error.what();
  }
}

TEST(StageMetrics, TheFunnelCountsEpisodesThatReachedAStageAndEveryOneBefore) {
  auto record = [](int approached, int grasped, int lifted) {
    EpisodeRecord r;
    // Written in another order than the task's: the funnel looks stages up by name.
    r.stages = {{"target_lifted", lifted}, {"target_approached", approached}, {"target_grasped", grasped}};
    return r;
  };
  const std::vector<EpisodeRecord> episodes = {record(10, 20, 30), record(10, -1, 40), record(-1, -1, -1),
                                               record(5, 9, -1)};
  const std::vector<FunnelStep> funnel =
      StageFunnel({{"target_approached"}, {"target_grasped"}, {"target_lifted"}}, episodes);
  ASSERT_EQ(funnel.size(), 3u);
  EXPECT_EQ(funnel[0].reached, 3);
  EXPECT_EQ(funnel[1].reached, 2);
  EXPECT_EQ(funnel[2].reached, 1) << "the second episode's lift without a grasp does not count";
  EXPECT_EQ(funnel[2].reached_alone, 2) << "on its own it does";
}

// Episodes of a cue task as a fixed camera sees them: never the cue (the neck is zeroed), then
// approached, grasped, lifted as given.
std::vector<EpisodeRecord> FixedCameraEpisodes() {
  auto record = [](int approached, int grasped, int lifted) {
    EpisodeRecord r;
    r.stages = {
        {"cue_fixated", -1}, {"target_approached", approached}, {"target_grasped", grasped}, {"target_lifted", lifted}};
    return r;
  };
  return {record(10, 20, 30), record(10, 20, 30), record(10, -1, -1), record(-1, -1, -1)};
}

TEST(StageMetrics, UnderAFixedViewTheGazeStageDoesNotApplyAndTheLaterStagesCountWithoutIt) {
  for (const char* task : {"conditional-pick", "wait-then-act"}) {
    SCOPED_TRACE(task);
    for (const CameraProtocol camera : {CameraProtocol::kFixed, CameraProtocol::kFixedOnly}) {
      const std::vector<FunnelStage> stages = FunnelStages(task, camera);
      ASSERT_EQ(stages.size(), 4u);
      EXPECT_EQ(stages[0].name, "cue_fixated");
      EXPECT_FALSE(stages[0].applies) << ToString(camera);
      for (std::size_t s = 1; s < stages.size(); ++s) EXPECT_TRUE(stages[s].applies) << stages[s].name;
    }
    for (const CameraProtocol camera : {CameraProtocol::kHead, CameraProtocol::kHeadOnly, CameraProtocol::kWristsOnly})
      EXPECT_TRUE(FunnelStages(task, camera)[0].applies) << ToString(camera) << ": the head moves";
  }
  const std::vector<FunnelStep> fixed =
      StageFunnel(FunnelStages("conditional-pick", CameraProtocol::kFixed), FixedCameraEpisodes());
  ASSERT_EQ(fixed.size(), 4u);
  EXPECT_FALSE(fixed[0].applies);
  EXPECT_EQ(fixed[1].reached, 3) << "approached, counted without the gaze it could not make";
  EXPECT_EQ(fixed[2].reached, 2);
  EXPECT_EQ(fixed[3].reached, 2);
  EXPECT_EQ(fixed[3].reached_alone, 2);
  const nlohmann::json json = FunnelJson(fixed);
  EXPECT_EQ(
      json[0],
      nlohmann::json({{"stage", "cue_fixated"}, {"applies", false}, {"reached", nullptr}, {"reached_alone", nullptr}}));
  EXPECT_EQ(json[1],
            nlohmann::json({{"stage", "target_approached"}, {"applies", true}, {"reached", 3}, {"reached_alone", 3}}));
  // The same episodes under head: the gaze applies and, never reached, stops the chain; each stage
  // on its own counts as under fixed.
  const std::vector<FunnelStep> head =
      StageFunnel(FunnelStages("conditional-pick", CameraProtocol::kHead), FixedCameraEpisodes());
  EXPECT_EQ(head[1].reached, 0);
  EXPECT_EQ(head[1].reached_alone, 3);
}

}  // namespace
}  // namespace tavis::batch::cell

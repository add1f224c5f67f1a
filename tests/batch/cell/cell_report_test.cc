// summary.json holds what earlier versions wrote for the same cell (the same keys, values and
// number types): tables and sweeps read old and new cells alike.
#include "batch/cell/cell_report.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "batch/cell/evaluation_cell.h"
#include "tests/batch/cell/example_cells.h"

namespace tavis::batch::cell {
namespace {

// One successful 15-tick episode run on two slots, as a cell's result after it ran.
CellResult OneEpisode(const EvaluationCellConfig& config) {
  CellResult result;
  result.config = config;
  result.render_width = 40;
  result.render_height = 30;
  EpisodeRecord record;
  record.success = true;
  record.end = engine::EpisodeEnd::kSuccess;
  record.length_steps = 5;
  record.length_control_ticks = 15;
  result.episodes = {record};
  result.successes = 1;
  result.envs = 2;
  result.wall_s = 1.5;
  result.control_ticks = 15;
  result.galt_fps = 60;
  result.galt_policy_rate_fps = 20;
  result.rendered_cameras = {"head"};
  result.rendered_images = 5;
  return result;
}

// summary.json as written, without its provenance section (new, and machine-dependent: the
// provenance tests check it).
nlohmann::json Summary(const CellResult& result) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("tavis_cell_report_test_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  WriteCellSummary(result, {3, 1}, dir.string());
  nlohmann::json summary;
  std::ifstream(dir / "summary.json") >> summary;
  std::filesystem::remove_all(dir);
  EXPECT_TRUE(summary.contains("provenance"));
  summary.erase("provenance");
  return summary;
}

// The same with its keys sorted and no spaces.
// The summary as earlier versions wrote it: without the keys issue 49 added (failure "events" and
// "motion", docs/events.md; FailureEvents.RecordsCarryEventsAndMotionThroughTheirJsonLine tests
// them), every other key and value unchanged.
std::string WrittenSummary(const CellResult& result) {
  nlohmann::json summary = Summary(result);
  EXPECT_TRUE(summary.at("events").is_object());
  EXPECT_TRUE(summary.at("motion").is_object());
  summary.erase("events");
  summary.erase("motion");
  return summary.dump();
}

TEST(CellReport, ABuiltInPolicysSummaryIsWhatEarlierVersionsWrote) {
  EXPECT_EQ(WrittenSummary(OneEpisode(HoldCellOnReachy())),
            R"({"actions_file":null,"camera":"fixed","ci_high":1.0,"ci_low":0.2065432914738929,"config_dir":"",)"
            R"("control_ticks":15,"control_ticks_per_s":10.0,"ends":{"success":1},"envs":2,"expert_hz":60,)"
            R"("galt":null,"galt_policy_rate":{"fps":20.0,"mean_s":null,"median_s":null,"n_episodes":0,)"
            R"("n_valid":0,"reasons":{},"std_s":null},"n_episodes":1,"n_successful":1,"policy":"hold",)"
            R"("render":{"cameras":["head"],"height":30,"images":5,"width":40},"resumed_episodes":1,)"
            R"("robot":"reachy2","seed":18446744073709551615,"simulator_faults":0,"split":"ood-init-pose",)"
            // Under the fixed camera the neck is zeroed: the gaze stage does not apply.
            R"("stages":[{"applies":false,"reached":null,"reached_alone":null,"stage":"cue_fixated"},)"
            R"({"applies":true,"reached":0,"reached_alone":0,"stage":"target_approached"},)"
            R"({"applies":true,"reached":0,"reached_alone":0,"stage":"target_grasped"},)"
            R"({"applies":true,"reached":0,"reached_alone":0,"stage":"target_lifted"}],"success_rate":1.0,)"
            R"("task":"wait-then-act","threads":3,"wall_s":1.5})");
}

TEST(CellReport, AServedPolicysSummaryIsWhatEarlierVersionsWrote) {
  EvaluationCellConfig config = ServedCellWithOptions();
  config.image_width = 40;
  config.image_height = 40;
  CellResult result = OneEpisode(config);
  result.requests = remote::RequestTimings{};
  result.requests->round_trip_ms = {1.0, 2.0};
  result.requests->envs_per_request = {1, 2};
  result.observation_keys_source = "aloha-source";
  result.layout_differences = {"diff one"};
  EXPECT_EQ(WrittenSummary(result),
            R"({"actions_file":null,"camera":"head","ci_high":1.0,"ci_low":0.2065432914738929,"config_dir":"",)"
            R"("control_ticks":15,"control_ticks_per_s":10.0,"ends":{"success":1},"envs":2,"expert_hz":60,)"
            R"("galt":{"fps":60.0,"mean_s":null,"median_s":null,"n_episodes":0,"n_valid":0,"reasons":{},)"
            R"("std_s":null},"galt_policy_rate":{"fps":20.0,"mean_s":null,"median_s":null,"n_episodes":0,)"
            R"("n_valid":0,"reasons":{},"std_s":null},"layout_differences":["diff one"],"n_episodes":1,)"
            R"("n_successful":1,"observation_dataset":"/data/set","observation_keys":"aloha-source",)"
            R"("policy":"openpi","policy_image":{"height":40,"width":40},"render":{"cameras":["head"],)"
            R"("height":30,"images":5,"width":40},"replan_steps":5,"requests":{"count":2,"env_requests":3,)"
            R"("mean_batch_size":1.5,"policy_ticks":0,"reconnects":0,"round_trip":{"count":2,"max_ms":2.0,)"
            R"("mean_ms":1.5,"median_ms":1.0,"p95_ms":2.0},"server_infer":null,"wait_s":0.0},)"
            R"("resumed_episodes":1,"robot":"gr1t2","seed":0,"server_metadata":[],)"
            R"("servers":["ws://a:1","ws://b:2"],"serving":"batched","simulator_faults":0,"split":"id",)"
            R"("stages":[{"applies":true,"reached":0,"reached_alone":0,"stage":"target_approached"},)"
            R"({"applies":true,"reached":0,"reached_alone":0,"stage":"target_grasped"},)"
            R"({"applies":true,"reached":0,"reached_alone":0,"stage":"target_lifted"}],"success_rate":1.0,)"
            R"("task":"clutter-pick-cube","threads":3,)"
            R"("wall_s":1.5})");
}

// The scripted expert succeeds under the fixed camera too; its funnel must say how far it got, not
// stop at a gaze stage a zeroed neck cannot make.
TEST(CellReport, AFixedCameraExpertsFunnelShowsTheStagesItReached) {
  for (const char* task : {"conditional-pick", "wait-then-act"}) {
    SCOPED_TRACE(task);
    EvaluationCellConfig config;
    config.task = task;
    config.robot = "gr1t2";
    config.camera = CameraProtocol::kFixed;
    config.policy = "expert";
    config.episodes = 3;
    config.envs = 3;
    config.config_dir = TAVIS_CONFIG_DIR;
    const CellResult result = RunEvaluationCell(config);
    ASSERT_EQ(result.successes, 3);
    const nlohmann::json stages = Summary(result).at("stages");
    ASSERT_EQ(stages.size(), 4u);
    EXPECT_EQ(stages[0].at("stage"), "cue_fixated");
    for (std::size_t s = 1; s < stages.size(); ++s) EXPECT_EQ(stages[s].at("reached"), 3) << stages[s];
    EXPECT_EQ(stages[0].value("applies", true), false) << "a zeroed neck cannot fixate the cue";
    EXPECT_TRUE(stages[0].at("reached").is_null());
    for (std::size_t s = 1; s < stages.size(); ++s) EXPECT_EQ(stages[s].value("reached_alone", -1), 3) << stages[s];
  }
}

}  // namespace
}  // namespace tavis::batch::cell

// A cell's plan: what PlanCell resolves from the settings (robot, scene, policy, layout, sizes,
// cameras, records) and what it refuses, naming the setting.
#include "batch/cell/cell_plan.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "batch/remote/server_contract.h"
#include "configs/yaml_reader.h"

namespace tavis::batch::cell {
namespace {

EvaluationCellConfig Cell(const std::string& policy) {
  EvaluationCellConfig config;
  config.policy = policy;
  config.config_dir = TAVIS_CONFIG_DIR;
  if (policy == "openpi") config.servers = {"ws://127.0.0.1:1"};  // planning connects to nothing
  if (policy == "replay") config.actions_file = "actions.csv";    // nor reads the actions
  return config;
}

template <typename Error = output::SettingError>
std::string ErrorOf(const EvaluationCellConfig& config) {
  try {
    PlanCell(config);
  } catch (const Error& error) {
    return error.what();
  }
  ADD_FAILURE() << "planned";
  return "";
}

TEST(CellPlan, TheExpertsPlanHasTheRobotInTheScenesAndItsRecordsAtTheControlRate) {
  const CellPlan plan = PlanCell(Cell("expert"));
  EXPECT_EQ(plan.scenario->name, "clutter-pick-cube");
  EXPECT_EQ(plan.model.robot.name, "gr1t2");
  EXPECT_GT(plan.model.num_objects(), 0) << "the task's layout is built";
  EXPECT_EQ(plan.policy, PolicyKind::kExpert);
  EXPECT_FALSE(plan.keys.has_value());
  EXPECT_EQ(plan.image_width, 640) << "the reference's size";
  EXPECT_EQ(plan.render_height, 480);
  EXPECT_TRUE(plan.cameras.empty()) << "the expert takes no images";
  EXPECT_EQ(plan.control_ticks_per_action, 1);
  EXPECT_EQ(plan.record.galt_stride, 1);
  EXPECT_DOUBLE_EQ(plan.record.galt_fps, 60.0);
  EXPECT_EQ(plan.record.policy_rate_stride, 3);
  EXPECT_EQ(plan.record.replay_stride, 0);
  EXPECT_TRUE(plan.identity.contains("robot_config"));
  EXPECT_FALSE(plan.identity.contains("observation_keys_config"));

  EvaluationCellConfig slow = Cell("expert");
  slow.expert_hz = 20;
  EXPECT_EQ(PlanCell(slow).record.replay_stride, 3) << "a 20 Hz expert's actions are kept for replay";
  EvaluationCellConfig fixed = Cell("expert");
  fixed.camera = CameraProtocol::kFixed;
  EXPECT_EQ(PlanCell(fixed).record.galt_stride, 0) << "no GALT without a head to lead";
}

TEST(CellPlan, ExtraCamerasAreRenderedAtTheImageSize) {
  EvaluationCellConfig config = Cell("hold");
  config.render_cameras = {"head", "right_wrist"};
  config.image_width = 64;
  config.image_height = 48;
  const CellPlan plan = PlanCell(config);
  EXPECT_EQ(plan.cameras, config.render_cameras);
  EXPECT_TRUE(plan.policy_cameras.empty());
  EXPECT_EQ(plan.render_width, 64);
  EXPECT_EQ(plan.render_height, 48);
  EXPECT_EQ(plan.control_ticks_per_action, 3) << "hold acts at the policy rate";
  EXPECT_EQ(plan.record.galt_stride, 3);
  EXPECT_EQ(plan.record.policy_rate_stride, 0);
}

TEST(CellPlan, AServedPolicysLayoutGivesItsCamerasAndSizes) {
  EvaluationCellConfig config = Cell("openpi");
  config.observation_keys = "aloha";  // 224 x 224, letterboxed
  config.camera = CameraProtocol::kFixed;
  config.render_cameras = {"left_wrist", "head"};
  config.image_width = 40;
  config.image_height = 40;
  const CellPlan plan = PlanCell(config);
  ASSERT_TRUE(plan.keys.has_value());
  EXPECT_EQ(plan.keys->source, "aloha");
  EXPECT_EQ(plan.image_width, 40) << "the size given takes the layout's place";
  EXPECT_EQ(plan.render_width, 40);
  EXPECT_EQ(plan.render_height, 30) << "letterboxed: the 4:3 cameras fitted into 40 x 40";
  EXPECT_EQ(plan.policy_cameras, (std::vector<std::string>{"fixed", "left_wrist", "right_wrist"}));
  EXPECT_EQ(plan.cameras, (std::vector<std::string>{"fixed", "left_wrist", "right_wrist", "head"}));
  EXPECT_EQ(plan.record.replay_stride, 3) << "a served policy's chunks are kept for replay";
  EXPECT_EQ(plan.record.galt_stride, 0);
  EXPECT_TRUE(plan.identity.contains("observation_keys_config"));
  EXPECT_TRUE(plan.layout_differences.empty()) << "no dataset named";
}

TEST(CellPlan, ADatasetsLayoutIsServedAndAnotherLayoutIsComparedWithIt) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("tavis_cell_plan_dataset_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir / "meta");
  const nlohmann::json image = {{"dtype", "video"}, {"shape", {48, 64, 3}}};
  EvaluationCellConfig config = Cell("openpi");
  const int state_size = static_cast<int>(PlanCell(config).model.robot.observation_state.size());
  std::ofstream(dir / "meta" / "info.json") << nlohmann::json{
      {"codebase_version", "v3.0"},
      {"features",
       {{"observation.state", {{"dtype", "float32"}, {"shape", {state_size}}}},
        {"observation.images.OBS_HEAD", image}}}}.dump();
  config.observation_dataset = dir.string();
  const CellPlan from_dataset = PlanCell(config);
  EXPECT_EQ(from_dataset.policy_cameras, std::vector<std::string>{"head"});
  EXPECT_EQ(from_dataset.image_width, 64);
  EXPECT_TRUE(from_dataset.layout_differences.empty());
  config.observation_keys_given = true;  // the default preset, tavis, at 320 x 240 with every camera
  const CellPlan compared = PlanCell(config);
  EXPECT_EQ(compared.image_width, 320);
  EXPECT_FALSE(compared.layout_differences.empty());
  std::filesystem::remove_all(dir);
}

// A contract as a server declaring the tavis layout at 96 x 96 for `task` and `robot` gives it
// ("": not declared).
remote::ServerContract DeclaredFor(const std::string& task, const std::string& robot, int state_size) {
  remote::ServerContract contract;
  contract.server = "ws://127.0.0.1:1";
  contract.keys = remote::ContractKeys();
  contract.keys.image_width = 96;
  contract.keys.image_height = 96;
  contract.state_size = state_size;
  contract.task = task;
  contract.robot = robot;
  return contract;
}

TEST(CellPlan, AContractOfTheCellsTaskAndRobotOrOfNoneIsAdopted) {
  EvaluationCellConfig config = Cell("openpi");
  const int state_size = static_cast<int>(PlanCell(config).model.robot.observation_state.size());
  for (const auto& [task, robot] : {std::pair<std::string, std::string>{"clutter-pick-cube", "gr1t2"},
                                    {"clutter-pick-cube", ""},
                                    {"", "gr1t2"},
                                    {"", ""}}) {
    config.declared_contract = DeclaredFor(task, robot, state_size);
    EXPECT_EQ(PlanCell(config).image_width, 96) << "declared '" << task << "' '" << robot << "'";
  }
}

TEST(CellPlan, AContractOfAnotherTaskOrRobotIsRefusedNamingBoth) {
  EvaluationCellConfig config = Cell("openpi");
  const int state_size = static_cast<int>(PlanCell(config).model.robot.observation_state.size());
  config.declared_contract = DeclaredFor("wait-then-act", "gr1t2", state_size);
  config.image_width = 224;  // contradicts the contract too, but the task is what is refused
  config.image_height = 224;
  const std::string task = ErrorOf<std::invalid_argument>(config);
  EXPECT_EQ(task.find("policy server ws://127.0.0.1:1's policy was trained for task wait-then-act; this cell is "
                      "clutter-pick-cube"),
            0u)
      << task;
  EXPECT_EQ(task.find("trained for robot"), std::string::npos) << "the robot agrees: " << task;
  config.declared_contract = DeclaredFor("clutter-pick-cube", "reachy2", state_size);
  const std::string robot = ErrorOf<std::invalid_argument>(config);
  EXPECT_NE(robot.find("was trained for robot reachy2; this cell's robot is gr1t2"), std::string::npos) << robot;
  EXPECT_EQ(robot.find("trained for task"), std::string::npos) << robot;
  config.declared_contract = DeclaredFor("wait-then-act", "reachy2", state_size);
  const std::string both = ErrorOf<std::invalid_argument>(config);
  EXPECT_NE(both.find("task wait-then-act"), std::string::npos) << both;
  EXPECT_NE(both.find("robot reachy2"), std::string::npos) << both;
}

TEST(CellPlan, PerturbationLevelsAreResolvedOnceIntoTheScene) {
  EvaluationCellConfig config = Cell("expert");
  config.perturbations = {"camera:fov-wide"};
  const CellPlan plan = PlanCell(config);
  ASSERT_EQ(plan.perturbations.size(), 1u);
  EXPECT_EQ(plan.perturbations[0].name, "fov-wide");
  EXPECT_NE(plan.model.view_perturbation.head_fov_scale,
            PlanCell(Cell("expert")).model.view_perturbation.head_fov_scale);
}

TEST(CellPlan, BadSettingsAreNamedByTheirKeys) {
  EvaluationCellConfig config = Cell("openpi");
  config.servers.clear();
  EXPECT_EQ(ErrorOf(config), "servers must name a policy server (ws://HOST:PORT) for policy 'openpi'");
  config = Cell("replay");
  config.actions_file.clear();
  EXPECT_NE(ErrorOf(config).find("actions_file must name"), std::string::npos);
  config = Cell("expert");
  config.observation_dataset = "/some/dataset";
  EXPECT_EQ(ErrorOf(config), "observation_dataset applies to policy 'openpi' only, got policy 'expert'");
  config = Cell("expert");
  config.image_height = 480;
  EXPECT_NE(ErrorOf(config).find("image_width and image_height must be given together"), std::string::npos);
  config = Cell("oracle");
  EXPECT_NE(ErrorOf<std::invalid_argument>(config).find("unknown policy 'oracle'"), std::string::npos);
  config = Cell("expert");
  config.robot = "robby";
  EXPECT_NE(ErrorOf<configs::ConfigError>(config).find("robby"), std::string::npos);
  config = Cell("expert");
  config.first_episode = 97;
  EXPECT_NE(ErrorOf<std::invalid_argument>(config).find("the first episode to run must be in [0, 96], got 97"),
            std::string::npos);
}

TEST(CellPlan, ARunContinuesOnlyFromAnEpisodeOfTheCell) {
  EvaluationCellConfig config = Cell("expert");
  config.episode_start = 4;
  config.episodes = 2;
  config.first_episode = 4;
  CellPlan plan = PlanCell(config);
  EXPECT_EQ(plan.end_episode(), 6);
  plan.ContinueFrom(6);  // nothing left to run
  EXPECT_EQ(plan.config.first_episode, 6);
  EXPECT_THROW(plan.ContinueFrom(3), std::invalid_argument);
  EXPECT_THROW(plan.ContinueFrom(7), std::invalid_argument);
}

}  // namespace
}  // namespace tavis::batch::cell

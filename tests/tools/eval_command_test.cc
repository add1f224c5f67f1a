// Runs the real `tavis` program (TAVIS_BINARY) and checks its exit status, output and files.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/batch/remote/policy_server_process.h"
#include "tool_runner.h"

namespace tavis::tools {
namespace {

using EvalCommand = TavisCommandTest;

TEST_F(EvalCommand, SmallCellWritesEpisodesSummaryAndOneLine) {
  const fs::path dir = root_ / "cell";
  const RunResult run = Run("eval --episodes 2 --envs 2 --seed 5 --quiet --out " + Quote(dir.string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.err, "") << "--quiet prints no progress";

  const std::vector<std::string> printed = Lines(run.out);
  ASSERT_EQ(printed.size(), 1u) << run.out;
  EXPECT_NE(printed[0].find("clutter-pick-cube gr1t2 id policy=expert"), std::string::npos) << printed[0];
  EXPECT_NE(printed[0].find(dir.string()), std::string::npos) << printed[0];

  const std::vector<std::string> lines = Lines(ReadText(dir / "episodes.jsonl"));
  ASSERT_EQ(lines.size(), 2u);
  int successes = 0;
  for (size_t i = 0; i < lines.size(); ++i) {
    const nlohmann::json episode = nlohmann::json::parse(lines[i]);
    for (const char* key : {"episode", "seed", "success", "end", "length_steps", "length_control_ticks"}) {
      EXPECT_TRUE(episode.contains(key)) << key << " missing in " << lines[i];
    }
    EXPECT_EQ(episode.at("episode").get<int>(), static_cast<int>(i));
    EXPECT_EQ(episode.at("seed").get<int>(), 5);
    EXPECT_GT(episode.at("length_steps").get<int>(), 0);
    EXPECT_EQ(episode.at("success").get<bool>(), episode.at("end").get<std::string>() == "success") << lines[i];
    // The 60 Hz expert's successful episodes carry GALT at its own rate and at the policy rate.
    for (const char* key : {"galt_reason", "galt_policy_rate_reason"}) {
      EXPECT_EQ(episode.contains(key), episode.at("success").get<bool>()) << key << " in " << lines[i];
    }
    successes += episode.at("success").get<bool>() ? 1 : 0;
  }

  const nlohmann::json summary = nlohmann::json::parse(ReadText(dir / "summary.json"));
  for (const char* key : {"task", "robot", "split", "policy", "n_episodes", "n_successful", "success_rate", "ci_low",
                          "ci_high", "wall_s"}) {
    EXPECT_TRUE(summary.contains(key)) << key << " missing in " << summary.dump();
  }
  EXPECT_EQ(summary.at("task"), "clutter-pick-cube");
  EXPECT_EQ(summary.at("robot"), "gr1t2");
  EXPECT_EQ(summary.at("split"), "id");
  EXPECT_EQ(summary.at("policy"), "expert");
  EXPECT_EQ(summary.at("n_episodes").get<int>(), 2);
  EXPECT_EQ(summary.at("n_successful").get<int>(), successes);
  const double rate = summary.at("success_rate").get<double>();
  EXPECT_DOUBLE_EQ(rate, successes / 2.0);
  EXPECT_LE(summary.at("ci_low").get<double>(), rate);
  EXPECT_GE(summary.at("ci_high").get<double>(), rate);
  EXPECT_LT(summary.at("ci_high").get<double>() - summary.at("ci_low").get<double>(), 1.0);
  EXPECT_GT(summary.at("wall_s").get<double>(), 0.0);

  // No temporary files are left next to the results: only them, the marker that says the folder is
  // a tavis cell and the (released) lock file.
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.insert(entry.path().filename().string());
  EXPECT_EQ(names, (std::set<std::string>{".tavis_lock", ".tavis_output", "cell.json", "episode_times.jsonl",
                                          "episodes.jsonl", "summary.json"}));
}

TEST_F(EvalCommand, ProfilePrintsSharesAndWritesProfileJsonWithoutChangingTheRecords) {
  const fs::path plain = root_ / "plain";
  const fs::path profiled = root_ / "profiled";
  const std::string cell = "eval --episodes 3 --envs 2 --seed 5 --quiet --out ";
  ASSERT_EQ(Run(cell + Quote(plain.string())).exit_code, 0);
  const RunResult run = Run(cell + Quote(profiled.string()) + " --profile");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("critical path (unlimited threads)"), std::string::npos) << run.out;
  EXPECT_EQ(ReadText(profiled / "episodes.jsonl"), ReadText(plain / "episodes.jsonl")) << "timing changes nothing";

  const nlohmann::json profile = nlohmann::json::parse(ReadText(profiled / "profile.json"));
  const nlohmann::json& stages = profile.at("stage_s");
  double work = 0.0;
  for (const char* stage : {"apply_actions", "step_physics", "reset", "render", "policy", "recording", "driver"}) {
    ASSERT_TRUE(stages.contains(stage)) << stage << " missing in " << stages.dump();
    EXPECT_GE(stages.at(stage).get<double>(), 0.0) << stage;
  }
  for (const auto& [name, seconds] : stages.items()) work += seconds.get<double>();
  EXPECT_GT(stages.at("step_physics").get<double>(), 0.0);
  EXPECT_NEAR(profile.at("work_s").get<double>(), work, 1e-9);
  // Every episode is timed once, with the ticks its record reports.
  const std::vector<std::string> records = Lines(ReadText(profiled / "episodes.jsonl"));
  const nlohmann::json& episodes = profile.at("episodes");
  ASSERT_EQ(episodes.size(), records.size());
  std::set<int> seen;
  for (const nlohmann::json& episode : episodes) {
    const int index = episode.at("episode").get<int>();
    ASSERT_TRUE(index >= 0 && index < 3) << episode.dump();
    seen.insert(index);
    EXPECT_GT(episode.at("seconds").get<double>(), 0.0);
    EXPECT_EQ(episode.at("control_ticks").get<int64_t>(),
              nlohmann::json::parse(records[index]).at("length_control_ticks").get<int64_t>());
  }
  EXPECT_EQ(seen.size(), 3u);
  // More threads never make the estimate longer, and no number of threads beats the critical path.
  const double critical_path = profile.at("critical_path_s").get<double>();
  double previous = profile.at("estimates").at("1").at("seconds").get<double>();
  for (const char* threads : {"2", "4", "8", "16"}) {
    const double estimate = profile.at("estimates").at(threads).at("seconds").get<double>();
    EXPECT_LE(estimate, previous + 1e-12) << threads;
    EXPECT_GE(estimate, critical_path - 1e-12) << threads;
    previous = estimate;
  }
}

TEST_F(EvalCommand, BadInputFailsNamingTheValueAndLeavesResultsAlone) {
  const fs::path dir = root_ / "cell";
  ASSERT_EQ(Run("eval --episodes 1 --envs 1 --quiet --out " + Quote(dir.string())).exit_code, 0);
  const std::map<std::string, std::string> before = Snapshot(dir);
  ASSERT_EQ(before.count((dir / "summary.json").string()), 1u);

  // (arguments, text the error must contain)
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--episodes 1 --task nope", "nope"},
      {"--episodes 1 --robot nope", "nope"},
      {"--episodes 1 --split nope", "nope"},
      {"--episodes 1 --policy nope", "nope"},
      {"--episodes 0", "got '0'"},
      {"--episodes -3", "got '-3'"},
      {"--episodes 1 --envs 0", "got '0'"},
      {"--episodes 1 --seed banana", "banana"},
      {"--episodes 1 --suite nope", "nope"},
      {"--episodes 1 --suite tavis-head --task wait-then-act", "--suite"},
      {"--episodes 1 --camera side", "side"},
  };
  for (const auto& [args, needle] : cases) {
    SCOPED_TRACE(args);
    const RunResult run = Run("eval --quiet " + args + " --out " + Quote(dir.string()));
    EXPECT_NE(run.exit_code, 0);
    EXPECT_NE(run.err.find(needle), std::string::npos) << "stderr: " << run.err;
    EXPECT_EQ(Snapshot(dir), before) << "a failed run must not touch the output directory";
  }
}

TEST_F(EvalCommand, SuiteRunsACellPerTaskAndPrintsTheSuiteMean) {
  const fs::path dir = root_ / "suite";
  const RunResult run = Run("eval --suite tavis-hands --episodes 1 --envs 1 --quiet --out " + Quote(dir.string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  for (const char* task : {"peeking-box", "occluded-reach", "blocked-clutter-pick-cube"}) {
    EXPECT_TRUE(fs::exists(dir / (std::string(task) + "_gr1t2_id_head_expert_s0") / "summary.json")) << task;
  }
  EXPECT_NE(run.out.find("tavis-hands gr1t2 id policy=expert camera=head: suite mean over 3 tasks"), std::string::npos)
      << run.out;
}

// The paired comparison: a head and a fixed cell of the same seed land in one table, the fixed
// one without GALT, and the policy's head images become fixed-camera images.
TEST_F(EvalCommand, HeadAndFixedCellsPairInOneTable) {
  for (const char* camera : {"head", "fixed"}) {
    const fs::path dir = root_ / "paired" / camera;
    const RunResult run = Run("eval --episodes 2 --envs 2 --seed 4 --quiet --camera " + std::string(camera) +
                              " --render-cameras head,left_wrist --image-size 32x24 --out " + Quote(dir.string()));
    ASSERT_EQ(run.exit_code, 0) << run.err;
    EXPECT_NE(run.out.find(std::string("camera=") + camera), std::string::npos) << run.out;
    const nlohmann::json summary = nlohmann::json::parse(ReadText(dir / "summary.json"));
    EXPECT_EQ(summary.at("camera"), camera);
    EXPECT_EQ(summary.at("galt").is_null(), std::string(camera) == "fixed") << summary.dump();
    for (const std::string& line : Lines(ReadText(dir / "episodes.jsonl"))) {
      EXPECT_EQ(nlohmann::json::parse(line).contains("galt_s"), std::string(camera) == "head") << line;
    }
  }
  const RunResult table = Run("table --in " + Quote((root_ / "paired").string()) + " --suite tavis-head --out " +
                              Quote((root_ / "paired_table").string()));
  ASSERT_EQ(table.exit_code, 0) << table.err;
  const std::string markdown = ReadText(root_ / "paired_table.md");
  EXPECT_NE(markdown.find("| gr1t2 id head | gr1t2 id fixed |"), std::string::npos) << markdown;
}

TEST_F(EvalCommand, RenderCamerasAreRenderedAndReported) {
  const fs::path dir = root_ / "cell";
  const RunResult run =
      Run("eval --episodes 1 --envs 1 --quiet --render-cameras head,right_wrist --image-size 32x24 --out " +
          Quote(dir.string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json summary = nlohmann::json::parse(ReadText(dir / "summary.json"));
  const nlohmann::json& render = summary.at("render");
  EXPECT_EQ(render.at("cameras"), nlohmann::json({"head", "right_wrist"}));
  EXPECT_EQ(render.at("width").get<int>(), 32);
  EXPECT_EQ(render.at("height").get<int>(), 24);
  const nlohmann::json episode = nlohmann::json::parse(Lines(ReadText(dir / "episodes.jsonl")).at(0));
  EXPECT_EQ(render.at("images").get<int>(), 2 * episode.at("length_steps").get<int>());
}

TEST_F(EvalCommand, BadRenderOptionsExitOneNamingTheValue) {
  const fs::path dir = root_ / "never";
  for (const auto& [args, needle] :
       std::vector<std::pair<std::string, std::string>>{{"--render-cameras head,nose", "'nose'"},
                                                        {"--render-cameras head,head", "'head' is listed twice"},
                                                        {"--render-cameras head --image-size 224", "'224'"},
                                                        {"--render-cameras head --image-size 0x10", "'0x10'"},
                                                        {"--render-cameras head --image-size 22x2y", "'22x2y'"}}) {
    SCOPED_TRACE(args);
    const RunResult run = Run("eval --episodes 1 --quiet " + args + " --out " + Quote(dir.string()));
    EXPECT_EQ(run.exit_code, 1);
    EXPECT_NE(run.err.find(needle), std::string::npos) << "stderr: " << run.err;
    EXPECT_FALSE(fs::exists(dir));
  }
}

TEST_F(EvalCommand, BadInputDoesNotCreateTheOutputDirectory) {
  const fs::path dir = root_ / "never";
  const RunResult run = Run("eval --quiet --robot nope --out " + Quote(dir.string()));
  EXPECT_NE(run.exit_code, 0);
  EXPECT_FALSE(fs::exists(dir));
}

// A robot file that used to abort inside ODE is now refused at load, naming file, key and value,
// before anything is written.
TEST_F(EvalCommand, BrokenRobotFileExitsOneNamingFileAndKeyAndWritesNothing) {
  const fs::path config = root_ / "config";
  fs::copy(TAVIS_CONFIG_DIR, config, fs::copy_options::recursive);
  const fs::path robot = config / "robots" / "gr1t2.yaml";
  std::string text = ReadText(robot);
  const size_t at = text.find("finger_mass: 0.1");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, std::string("finger_mass: 0.1").size(), "finger_mass: 0.0");
  std::ofstream(robot, std::ios::binary) << text;
  const std::map<std::string, std::string> before = Snapshot(root_);

  const fs::path out = root_ / "cell";
  const RunResult run =
      Run("eval --config-dir " + Quote(config.string()) + " --episodes 1 --quiet --out " + Quote(out.string()));
  EXPECT_EQ(run.exit_code, 1) << run.err;
  EXPECT_NE(run.err.find(robot.string() + ": gripper.finger_mass: got 0.0"), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(Snapshot(root_), before) << "nothing is written";
}

TEST_F(EvalCommand, HelpExitsZeroAndListsOptions) {
  const RunResult run = Run("eval --help");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  for (const char* option : {"--task", "--robot", "--split", "--policy", "--episodes", "--seed", "--out",
                             "--render-cameras", "--image-size", "--server", "--replan-steps", "--server-timeout"}) {
    EXPECT_NE(run.out.find(option), std::string::npos) << option << " missing in:\n" << run.out;
  }
}

// A served policy through the real program: its episodes' actions are saved and replay them
// without the server; a server that fails leaves no results.
TEST_F(EvalCommand, ServedPolicyCellSavesReplayableActionsAndAFailingServerLeavesNoResults) {
  batch::remote::testing::PolicyServerProcess server(
      {"--horizon", "10", "--action-dim", "19", "--action-scale", "0.001"});
  const fs::path dir = root_ / "served";
  const std::string cell = "eval --episodes 2 --envs 2 --seed 6 --quiet --image-size 32x24 ";
  const RunResult run = Run(cell + "--policy openpi --server " + server.address() + " --out " + Quote(dir.string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json summary = nlohmann::json::parse(ReadText(dir / "summary.json"));
  EXPECT_EQ(summary.at("policy"), "openpi");
  EXPECT_EQ(summary.at("servers"), nlohmann::json::array({server.address()}));
  EXPECT_GT(summary.at("requests").at("count").get<int>(), 0) << summary.dump();
  const std::vector<std::string> served = Lines(ReadText(dir / "episodes.jsonl"));
  ASSERT_EQ(served.size(), 2u);

  const fs::path replay_dir = root_ / "replayed";
  const RunResult replay =
      Run("eval --episodes 1 --envs 1 --seed 6 --quiet --policy replay --actions " +
          Quote((dir / "actions" / "episode_0.csv.gz").string()) + " --out " + Quote(replay_dir.string()));
  ASSERT_EQ(replay.exit_code, 0) << replay.err;
  EXPECT_EQ(Lines(ReadText(replay_dir / "episodes.jsonl")), std::vector<std::string>{served[0]});
  EXPECT_TRUE(fs::exists(dir / "actions" / "episode_1.csv.gz"));
  // Episode 1 alone, from the whole cell's actions folder: the same record, without running episode 0.
  const fs::path one_dir = root_ / "episode_1";
  const RunResult one = Run("eval --episode 1 --envs 1 --seed 6 --quiet --policy replay --actions " +
                            Quote((dir / "actions").string()) + " --out " + Quote(one_dir.string()));
  ASSERT_EQ(one.exit_code, 0) << one.err;
  EXPECT_EQ(Lines(ReadText(one_dir / "episodes.jsonl")), std::vector<std::string>{served[1]});

  batch::remote::testing::PolicyServerProcess failing(
      {"--horizon", "10", "--action-dim", "19", "--action-scale", "0.001", "--fail-at-request", "3"});
  const fs::path failed_dir = root_ / "failed";
  const RunResult failed =
      Run(cell + "--policy openpi --server " + failing.address() + " --out " + Quote(failed_dir.string()));
  EXPECT_NE(failed.exit_code, 0);
  EXPECT_NE(failed.err.find("RuntimeError: test policy asked to fail at request 3"), std::string::npos) << failed.err;
  EXPECT_FALSE(fs::exists(failed_dir / "summary.json"));
}

// `--episode I` runs episode I of the seed alone: its record equals line I of the full cell, in a
// folder named for it by default; a resume keeps the episode, and it does not combine with --episodes.
TEST_F(EvalCommand, OneChosenEpisodeEqualsItsLineInTheFullCell) {
  const fs::path full = root_ / "full";
  ASSERT_EQ(Run("eval --episodes 3 --envs 3 --seed 8 --quiet --out " + Quote(full.string())).exit_code, 0);
  const std::vector<std::string> lines = Lines(ReadText(full / "episodes.jsonl"));
  ASSERT_EQ(lines.size(), 3u);
  const fs::path one = root_ / "one";
  const RunResult run = Run("eval --episode 2 --seed 8 --quiet --out " + Quote(one.string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(Lines(ReadText(one / "episodes.jsonl")), std::vector<std::string>{lines[2]});
  const nlohmann::json summary = nlohmann::json::parse(ReadText(one / "summary.json"));
  EXPECT_EQ(summary.at("n_episodes").get<int>(), 1);
  EXPECT_EQ(nlohmann::json::parse(ReadText(one / "cell.json")).at("episode_start").get<int>(), 2);
  EXPECT_FALSE(nlohmann::json::parse(ReadText(full / "cell.json")).contains("episode_start"));

  // The default folder names the episode, so it never takes the full cell's place.
  const RunResult named = RunIn(root_, "eval --episode 1 --seed 8 --quiet");
  ASSERT_EQ(named.exit_code, 0) << named.err;
  EXPECT_TRUE(fs::exists(root_ / "results" / "clutter-pick-cube_gr1t2_id_head_expert_s8_ep1" / "summary.json"))
      << named.out;

  const RunResult both = Run("eval --episode 1 --episodes 4 --quiet --out " + Quote((root_ / "both").string()));
  EXPECT_NE(both.exit_code, 0);
  EXPECT_NE(both.err.find("--episodes"), std::string::npos) << both.err;
  EXPECT_FALSE(fs::exists(root_ / "both"));
  const RunResult negative = Run("eval --episode -1 --quiet --out " + Quote((root_ / "negative").string()));
  EXPECT_NE(negative.exit_code, 0);
  EXPECT_NE(negative.err.find("-1"), std::string::npos) << negative.err;
}

using GaltCommand = EvalCommand;

TEST_F(GaltCommand, HelpExitsZero) {
  const RunResult run = Run("galt --help");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("--fps"), std::string::npos) << run.out;
}

}  // namespace
}  // namespace tavis::tools

// Runs the real `tavis` program (TAVIS_BINARY) and checks its exit status, output and files.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace tavis::tools {
namespace {

namespace fs = std::filesystem;

struct RunResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string Quote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (!line.empty()) lines.push_back(line);
  }
  return lines;
}

class EvalCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = fs::temp_directory_path() /
            ("tavis_tools_test_" + std::to_string(getpid()) + "_" + info->test_suite_name() + "_" + info->name());
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(root_, ignored);
  }

  // Runs `tavis ARGS`, capturing stdout and stderr separately.
  RunResult Run(const std::string& args) const {
    const fs::path out = root_ / "stdout.txt";
    const fs::path err = root_ / "stderr.txt";
    const std::string command =
        Quote(TAVIS_BINARY) + " " + args + " >" + Quote(out.string()) + " 2>" + Quote(err.string());
    const int status = std::system(command.c_str());
    RunResult result;
    result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    result.out = ReadText(out);
    result.err = ReadText(err);
    fs::remove(out);
    fs::remove(err);
    return result;
  }

  // Every regular file under `dir` with its content.
  static std::map<std::string, std::string> Snapshot(const fs::path& dir) {
    std::map<std::string, std::string> files;
    for (const auto& entry : fs::recursive_directory_iterator(dir)) {
      if (entry.is_regular_file()) files[entry.path().string()] = ReadText(entry.path());
    }
    return files;
  }

  fs::path root_;
};

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

  // No temporary files are left next to the results.
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.insert(entry.path().filename().string());
  EXPECT_EQ(names, (std::set<std::string>{"episodes.jsonl", "summary.json"}));
}

TEST_F(EvalCommand, BadInputFailsNamingTheValueAndLeavesResultsAlone) {
  const fs::path dir = root_ / "cell";
  ASSERT_EQ(Run("eval --episodes 1 --envs 1 --quiet --out " + Quote(dir.string())).exit_code, 0);
  const std::map<std::string, std::string> before = Snapshot(dir);
  ASSERT_EQ(before.count((dir / "summary.json").string()), 1u);

  // (arguments, text the error must contain)
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--episodes 1 --task nope", "nope"},   {"--episodes 1 --robot nope", "nope"},
      {"--episodes 1 --split nope", "nope"},  {"--episodes 1 --policy nope", "nope"},
      {"--episodes 0", "got 0"},              {"--episodes -3", "got -3"},
      {"--episodes 1 --envs 0", "got 0"},     {"--episodes 1 --seed banana", "banana"},
  };
  for (const auto& [args, needle] : cases) {
    SCOPED_TRACE(args);
    const RunResult run = Run("eval --quiet " + args + " --out " + Quote(dir.string()));
    EXPECT_NE(run.exit_code, 0);
    EXPECT_NE(run.err.find(needle), std::string::npos) << "stderr: " << run.err;
    EXPECT_EQ(Snapshot(dir), before) << "a failed run must not touch the output directory";
  }
}

TEST_F(EvalCommand, BadInputDoesNotCreateTheOutputDirectory) {
  const fs::path dir = root_ / "never";
  const RunResult run = Run("eval --quiet --robot nope --out " + Quote(dir.string()));
  EXPECT_NE(run.exit_code, 0);
  EXPECT_FALSE(fs::exists(dir));
}

TEST_F(EvalCommand, HelpExitsZeroAndListsOptions) {
  const RunResult run = Run("eval --help");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  for (const char* option : {"--task", "--robot", "--split", "--policy", "--episodes", "--seed", "--out"}) {
    EXPECT_NE(run.out.find(option), std::string::npos) << option << " missing in:\n" << run.out;
  }
}

using GaltCommand = EvalCommand;

TEST_F(GaltCommand, HelpExitsZero) {
  const RunResult run = Run("galt --help");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("--fps"), std::string::npos) << run.out;
}

}  // namespace
}  // namespace tavis::tools

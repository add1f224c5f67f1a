// `tavis demos` given bad input, through the real program: it exits 1 naming the bad value and
// leaves --out as it was; a non-empty --out is refused unless --overwrite.
#include <gtest/gtest.h>

#include <map>
#include <sstream>
#include <string>

#include "tool_runner.h"

namespace tavis::tools {
namespace {

using DemosCommand = TavisCommandTest;

// A quick valid run (one episode, one small camera) with `changes` ("--option value" pairs)
// replacing its values: the CLI takes each option once.
std::string Demos(const std::string& changes = "") {
  std::map<std::string, std::string> options = {
      {"--episodes", "1"}, {"--envs", "1"}, {"--fps", "20"}, {"--image-size", "64x48"}, {"--cameras", "head"}};
  std::istringstream words(changes);
  for (std::string option, value; words >> option >> value;) options[option] = value;
  std::string args = "demos --quiet";
  for (const auto& [option, value] : options) args += " " + option + " " + Quote(value);
  return args;
}

TEST_F(DemosCommand, NonEmptyOutIsRefusedAndOverwriteReplacesIt) {
  const fs::path out = root_ / "dataset";
  fs::create_directories(out);
  { std::ofstream(out / "keep.txt") << "mine"; }
  const RunResult refused = Run(Demos() + " --out " + Quote(out.string()));
  EXPECT_EQ(refused.exit_code, 1) << refused.err;
  EXPECT_NE(refused.err.find("not empty"), std::string::npos) << refused.err;
  EXPECT_EQ(ReadText(out / "keep.txt"), "mine");
  EXPECT_EQ(Snapshot(out).size(), 1u) << "nothing added beside the user's file";

  // --overwrite replaces only a dataset tavis wrote: the user's file is named and kept.
  const RunResult foreign = Run(Demos() + " --overwrite --out " + Quote(out.string()));
  EXPECT_EQ(foreign.exit_code, 1) << foreign.err;
  EXPECT_NE(foreign.err.find("keep.txt"), std::string::npos) << foreign.err;
  EXPECT_EQ(ReadText(out / "keep.txt"), "mine");

  const fs::path dataset = root_ / "tavis-dataset";
  ASSERT_EQ(Run(Demos("--seed 1") + " --out " + Quote(dataset.string())).exit_code, 0);
  const std::string first = ReadText(dataset / "tavis_demos.json");
  const RunResult replaced = Run(Demos("--seed 2") + " --overwrite --out " + Quote(dataset.string()));
  ASSERT_EQ(replaced.exit_code, 0) << replaced.err;
  EXPECT_TRUE(fs::exists(dataset / "meta/info.json"));
  EXPECT_NE(ReadText(dataset / "tavis_demos.json").find("\"seed\": 2"), std::string::npos);
  EXPECT_EQ(first.find("\"seed\": 2"), std::string::npos);
}

struct BadValue {
  const char* name;
  const char* args;
  const char* named;  // what the error message must name
};

// ctest's test names show the arguments, not the struct's bytes.
void PrintTo(const BadValue& value, std::ostream* out) { *out << value.args; }

class DemosBadValue : public TavisCommandTest, public ::testing::WithParamInterface<BadValue> {};

TEST_P(DemosBadValue, ExitsOneNamingItAndCreatesNothing) {
  const fs::path out = root_ / "dataset";
  const RunResult run = Run(Demos(GetParam().args) + " --out " + Quote(out.string()));
  EXPECT_EQ(run.exit_code, 1) << run.err;
  EXPECT_NE(run.err.find(GetParam().named), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(out)) << "a bad value created " << out;
}

// The same values with --overwrite over an existing dataset: refused before anything is removed.
TEST_P(DemosBadValue, OverwriteKeepsWhatIsThere) {
  const fs::path out = root_ / "dataset";
  fs::create_directories(out);
  { std::ofstream(out / "keep.txt") << "mine"; }
  const RunResult run = Run(Demos(GetParam().args) + " --overwrite --out " + Quote(out.string()));
  EXPECT_EQ(run.exit_code, 1) << run.err;
  EXPECT_EQ(ReadText(out / "keep.txt"), "mine") << "a bad value removed the user's files";
}

INSTANTIATE_TEST_SUITE_P(
    Values, DemosBadValue,
    ::testing::Values(BadValue{"fps", "--fps 30", "--fps must be 60 or 20, got 30"},
                      BadValue{"expert_hz", "--expert-hz 30", "--expert-hz must be 60 or 20, got 30"},
                      BadValue{"codec", "--codec vp9", "vp9"}, BadValue{"format", "--format v4", "v4"},
                      BadValue{"odd_size", "--image-size 65x48", "65"},
                      BadValue{"camera", "--cameras head,chest", "chest"}, BadValue{"task", "--task nope", "nope"},
                      BadValue{"attempts", "--max-attempts 1 --episodes 2", "--max-attempts 1"}),
    [](const ::testing::TestParamInfo<BadValue>& param) { return std::string(param.param.name); });

TEST_F(DemosCommand, UnwritableOutFailsNamingIt) {
  const RunResult run = Run(Demos() + " --out /proc/tavis-demos-test/dataset");
  EXPECT_EQ(run.exit_code, 1) << run.err;
  EXPECT_NE(run.err.find("/proc/tavis-demos-test"), std::string::npos) << run.err;
}

// A resume that leaves out the recording's --perturb is another recording: refused naming the
// level, and nothing is written (it once finished a runtime:move recording unperturbed, its
// tavis_demos.json saying "perturbations": []).
TEST_F(DemosCommand, ResumeThatLeavesOutThePerturbationIsRefusedNamingIt) {
  const fs::path out = root_ / "dataset";
  const std::string args = Demos("--episodes 8") + " --threads 1 --out " + Quote(out.string());
  ASSERT_TRUE(KillWhenLinesAppear(args + " --perturb runtime:move",
                                  out / ".tavis_spool" / "episode_000000" / "episode.json", 1, SIGKILL))
      << "the recording finished before it could be interrupted";
  // What the recording holds: the lock file keeps the killed run's holder note until the next run takes it.
  const auto recorded = [&out] {
    std::map<std::string, std::string> files = Snapshot(out);
    files.erase((out / ".tavis_lock").string());
    return files;
  };
  const auto before = recorded();
  const RunResult resumed = Run(args + " --resume");
  EXPECT_EQ(resumed.exit_code, 1);
  EXPECT_NE(resumed.err.find("--resume with other settings than the interrupted recording: perturbations "
                             "[{\"axis\":\"runtime\",\"level\":\"move\""),
            std::string::npos)
      << resumed.err;
  EXPECT_NE(resumed.err.find("}] -> unset"), std::string::npos) << resumed.err;
  EXPECT_EQ(recorded(), before) << "a refused resume wrote into the dataset";
  EXPECT_FALSE(fs::exists(out / "tavis_demos.json"));
}

}  // namespace
}  // namespace tavis::tools

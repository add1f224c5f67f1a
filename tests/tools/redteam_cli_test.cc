// Bad input through the real program: each case must exit with status 1, print a message naming
// the bad value, and write nothing (no result folder, no table, no default results/ folder).
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>

#include "tool_runner.h"

namespace tavis::tools {
namespace {

class RedTeamCliTest : public TavisCommandTest {
 protected:
  // Runs `tavis ARGS` from inside root_ (so that a default output folder would land there) and
  // expects a refusal naming `expected`, with root_ unchanged. `limits` runs before (ulimit).
  void ExpectRefused(const std::string& args, const std::string& expected, const std::string& limits = "") {
    const std::map<std::string, std::string> before = Snapshot(root_);
    const std::set<fs::path> paths_before = Paths();
    const fs::path out = root_.string() + ".stdout";
    const fs::path err = root_.string() + ".stderr";
    const std::string command = "cd " + Quote(root_.string()) + " && " + limits + Quote(TAVIS_BINARY) + " " + args +
                                " >" + Quote(out.string()) + " 2>" + Quote(err.string());
    const int status = std::system(command.c_str());
    const std::string output = ReadText(out) + ReadText(err);
    fs::remove(out);
    fs::remove(err);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 1) << args << "\n" << output;
    EXPECT_NE(output.find(expected), std::string::npos) << args << "\nwanted: " << expected << "\ngot: " << output;
    EXPECT_EQ(Snapshot(root_), before) << args << ": wrote files";
    EXPECT_EQ(Paths(), paths_before) << args << ": created folders";
  }

  // Every file and folder under root_.
  std::set<fs::path> Paths() const {
    std::set<fs::path> paths;
    for (const auto& entry : fs::recursive_directory_iterator(root_)) paths.insert(entry.path());
    return paths;
  }

  void WriteFile(const fs::path& path, const std::string& text) {
    fs::create_directories(path.parent_path());
    std::ofstream(path) << text;
  }

  // A cell's summary.json with the keys `tavis table` reads.
  void WriteSummary(const std::string& folder, const std::string& robot = "gr1t2", const std::string& split = "id",
                    const std::string& camera = "head", const std::string& task = "clutter-pick-cube") {
    WriteFile(root_ / "cells" / folder / "summary.json",
              R"({"task": ")" + task + R"(", "robot": ")" + robot + R"(", "split": ")" + split + R"(", "camera": ")" +
                  camera + R"(", "policy": "expert", "seed": 0, "n_episodes": 4, "n_successful": 4})");
  }
};

constexpr const char* kSeedRange = "--seed must be an integer from 0 to 18446744073709551615, got ";

TEST_F(RedTeamCliTest, CountsAndRatesOutsideTheirRangeAreNamedPlainly) {
  // Before: CLI11's "Could not convert" or a bound printed with 309 digits.
  ExpectRefused("eval --episodes 1e400 --out out", "--episodes: must be an integer from 1 to 100000000, got '1e400'");
  ExpectRefused("eval --episodes 99999999999 --out out", "got '99999999999'");
  ExpectRefused("eval --episodes ten --out out", "--episodes: must be an integer from 1 to 100000000, got 'ten'");
  ExpectRefused("eval --envs 5000 --out out", "--envs: must be an integer from 1 to 4096, got '5000'");
  ExpectRefused("eval --threads -1 --out out", "--threads: must be an integer from 0 to 1024, got '-1'");
  ExpectRefused("eval --replan-steps -2 --out out", "--replan-steps: must be an integer from 0 to 1000000, got '-2'");
  ExpectRefused("eval --server-timeout 0 --out out", "--server-timeout: must be a number from 0.001 to 86400, got '0'");
  ExpectRefused("demos --max-attempts -1 --out out",
                "--max-attempts: must be an integer from 0 to 100000000, got '-1'");
  ExpectRefused("render --steps -1 --out out", "--steps: must be an integer from 0 to 1000000, got '-1'");
  ExpectRefused("render --width 0 --out out", "--width: must be an integer from 1 to 8192, got '0'");
  ExpectRefused("audit --task clutter-pick-cube --robot gr1t2 --episodes 0 --out out",
                "--episodes: must be an integer from 1 to 100000000, got '0'");
}

TEST_F(RedTeamCliTest, SeedsOutsideSixtyFourBitsAreRefusedByEveryCommand) {
  const std::string out = " --out out";
  ExpectRefused("eval --episodes 1 --seed -1" + out, std::string(kSeedRange) + "-1");
  ExpectRefused("eval --episodes 1 --seed 18446744073709551616" + out,
                std::string(kSeedRange) + "18446744073709551616");
  ExpectRefused("render --seed 18446744073709551616" + out, std::string(kSeedRange) + "18446744073709551616");
  ExpectRefused("audit --task clutter-pick-cube --robot gr1t2 --seed 99999999999999999999" + out,
                std::string(kSeedRange) + "99999999999999999999");
  ExpectRefused("demos --episodes 1 --seed -1" + out, std::string(kSeedRange) + "-1");
  ExpectRefused("eval --episodes 1 --seed 1e3" + out, std::string(kSeedRange) + "1e3");
}

TEST_F(RedTeamCliTest, MisspeltCommandIsNamed) {
  ExpectRefused("evl --episodes 1",
                "unknown command 'evl' (known: eval, demos, galt, render, table, audit, sweep, compare, verify)");
}

TEST_F(RedTeamCliTest, MissingOrEmptyConfigDirIsNamed) {
  ExpectRefused("eval --episodes 1 --config-dir /nonexistent/configs --out out",
                "--config-dir '/nonexistent/configs' does not exist");
  fs::create_directories(root_ / "empty");
  ExpectRefused("render --config-dir " + Quote((root_ / "empty").string()) + " --out out",
                "--config-dir '" + (root_ / "empty").string() + "' has no robots/*.yaml");
}

TEST_F(RedTeamCliTest, NumberBeyondDoubleRangeIsOutOfRange) {
  ExpectRefused("galt --fps 1e400 missing.csv", "--fps 1e400 is out of range");
  // In a robot file: yaml-cpp refuses the literal as if it were no number at all.
  const fs::path configs = root_ / "configs";
  fs::copy(fs::path(TAVIS_CONFIG_DIR), configs, fs::copy_options::recursive);
  const fs::path robot = configs / "robots" / "gr1t2.yaml";
  std::string text = ReadText(robot);
  const std::size_t key = text.find("damping: ");
  ASSERT_NE(key, std::string::npos);
  text.replace(key, text.find('\n', key) - key, "damping: 1e400");
  WriteFile(robot, text);
  ExpectRefused("eval --episodes 1 --config-dir " + Quote(configs.string()) + " --out out", "'1e400'");
  ExpectRefused("eval --episodes 1 --config-dir " + Quote(configs.string()) + " --out out", "out of range");
}

TEST_F(RedTeamCliTest, OutOfMemoryIsReportedPlainly) {
  // Terapixel images for one env: far more than any machine has. The address-space limit makes
  // sure the allocation fails rather than being overcommitted.
  ExpectRefused("eval --episodes 1 --envs 1 --render-cameras head --image-size 1000000x1000000 --out out",
                "out of memory (try fewer --envs or a smaller --image-size)", "ulimit -v 16000000 && ");
}

TEST_F(RedTeamCliTest, TableRefusesACopiedCellNamingBothFolders) {
  WriteSummary("a");
  WriteSummary("b");
  ExpectRefused("table --in cells --suite tavis-head --out table", "cells/a/summary.json and cells/b/summary.json");
}

TEST_F(RedTeamCliTest, TableNamesAnUnknownNameWithItsFile) {
  WriteSummary("a", "gr1t3");
  ExpectRefused("table --in cells --suite tavis-head --out table", "cells/a/summary.json: unknown robot 'gr1t3'");
  fs::remove_all(root_ / "cells");
  WriteSummary("a", "gr1t2", "ood-spacial");
  ExpectRefused("table --in cells --suite tavis-head --out table", "cells/a/summary.json: unknown split 'ood-spacial'");
  fs::remove_all(root_ / "cells");
  WriteSummary("a", "gr1t2", "id", "wrist");
  ExpectRefused("table --in cells --suite tavis-head --out table", "cells/a/summary.json: unknown camera 'wrist'");
  fs::remove_all(root_ / "cells");
  WriteSummary("a", "gr1t2", "id", "head", "clutter-pick-cub");
  ExpectRefused("table --in cells --suite tavis-head --out table",
                "cells/a/summary.json: unknown task 'clutter-pick-cub'");
}

TEST_F(RedTeamCliTest, GaltFpsOutsideOneToAThousandHertz) {
  WriteFile(root_ / "episode.csv", "0,0,0,1,0,0,0,0,0,0,1,0,0,0,0,0,0,-1,-1\n");
  for (const std::string fps : {"1e9", "1e-300", "1e308", "0.5", "1001", "nan", "-20"}) {
    ExpectRefused("galt --fps " + fps + " episode.csv", "--fps must be a number from 1 to 1000, got " + fps);
  }
  ExpectRefused("galt --dataset nowhere --fps 1e9", "--fps must be a number from 1 to 1000, got 1e9");
}

TEST_F(RedTeamCliTest, EvalProvenanceOptionsAreNotIgnored) {
  WriteFile(root_ / "actions.csv", "0,0,0,1,0,0,0,0,0,0,1,0,0,0,0,0,0,-1,-1\n");
  ExpectRefused("eval --episodes 1 --actions actions.csv --out out",
                "--actions applies to --policy replay only, got --policy expert");
  ExpectRefused("eval --episodes 1 --policy hold --expert-hz 20 --out out",
                "--expert-hz applies to --policy expert only, got --policy hold");
  ExpectRefused("eval --episodes 1 --out ''", "--out must name a folder, got an empty string");
}

// The library names a bad setting by its key (cell.json's); the command names the flag it was
// given with.
TEST_F(RedTeamCliTest, SettingsTheLibraryRefusesAreNamedByTheirFlags) {
  ExpectRefused("eval --episodes 1 --expert-hz 30 --out out", "--expert-hz must be 60 or 20, got 30");
  ExpectRefused("eval --episodes 1 --policy openpi --out out",
                "--server must name a policy server (ws://HOST:PORT) for policy 'openpi'");
  ExpectRefused("eval --episodes 1 --policy replay --out out", "--actions must name a CSV of actions");
}

// A word where a choice is due names the values allowed; two servers in one --server are named
// before anything is written or asked. Before: "Could not convert: --fps = sixty", and "port ''
// is not a number" or a server "[a:1,b]:2" that could not be resolved.
TEST_F(RedTeamCliTest, AWordForAChoiceAndTwoServersInOneValueAreNamed) {
  ExpectRefused("demos --episodes 1 --fps sixty --out out", "--fps: must be 60 or 20, got 'sixty'");
  ExpectRefused("eval --episodes 1 --expert-hz sixty --out out", "--expert-hz: must be 60 or 20, got 'sixty'");
  const std::string served = "eval --episodes 1 --policy openpi --server-timeout 0.001 --out out --server ";
  ExpectRefused(served + "ws://127.0.0.1:1,ws://127.0.0.1:2",
                "--server: policy server URL 'ws://127.0.0.1:1,ws://127.0.0.1:2': holds more than one URL (one "
                "server per URL)");
  ExpectRefused(served + "ws://127.0.0.1:1ws://127.0.0.1:2", "holds more than one URL");
  ExpectRefused(served + "ws://127.0.0.1:1,127.0.0.1:2",
                "--server: policy server URL 'ws://127.0.0.1:1,127.0.0.1:2': host '127.0.0.1:1,127.0.0.1' holds ',', "
                "which no host name has (one server per URL)");
}

// A device, a FIFO or a folder given as an input file is named as such. Before: /dev/zero was read
// without end (memory growing until "read error"), a folder as a spec gave yaml-cpp's "bad file".
TEST_F(RedTeamCliTest, InputsThatAreNotRegularFilesAreNamedNotRead) {
  ExpectRefused("sweep /dev/zero --out out", "/dev/zero: the sweep spec is a character device, not a regular file");
  ExpectRefused("sweep . --out out", ".: the sweep spec is a directory, not a file");
  ExpectRefused("eval --episodes 1 --policy replay --actions /dev/zero --out out",
                "/dev/zero: is a character device, not a regular file");
  ExpectRefused("galt --fps 20 /dev/zero", "/dev/zero: is a character device, not a regular file");
}

// A sweep whose policy names a file that is not there is refused before it writes anything,
// naming the spec file and key. Before: the sweep folder was made and the first cell failed with
// "nothere.csv: no such file", naming neither.
TEST_F(RedTeamCliTest, SweepSpecFileErrorsAreFoundBeforeAnythingIsWritten) {
  const std::string cells =
      "tasks: [clutter-pick-cube]\nrobots: [gr1t2]\nsplits: [id]\ncameras: [head]\nseeds: [0]\nepisodes: 2\n";
  WriteFile(root_ / "replay.yaml", cells + "policy:\n  name: replay\n  actions: nothere.csv\n");
  ExpectRefused("sweep replay.yaml --out out", "replay.yaml: policy.actions: nothere.csv: no such file");
  WriteFile(root_ / "keys.yaml",
            cells + "policy:\n  name: openpi\n  servers: [ws://127.0.0.1:1]\n  keys: nothere.yaml\n");
  ExpectRefused("sweep keys.yaml --out out",
                "keys.yaml: policy.keys: observation keys 'nothere.yaml' are neither a preset");
}

// A damaged manifest is named with what is wrong. Before: nlohmann's "[json.exception.type_error.305]
// cannot use operator[] with a string argument with string", naming no file.
TEST_F(RedTeamCliTest, DamagedSweepManifestIsNamedWithWhatIsWrong) {
  const std::string valid =
      R"({"spec": {}, "spec_yaml": "", "version": "v", "shard": {"index": 0, "count": 1}, "cells": {}})";
  const std::string manifest = "shard/manifest.json";
  WriteFile(root_ / manifest, valid);
  ASSERT_EQ(Run("sweep merge --out " + Quote((root_ / "merged").string()) + " " + Quote((root_ / "shard").string()))
                .err.find("damaged"),
            std::string::npos)
      << "the premise: the valid manifest passes the checks";
  fs::remove_all(root_ / "merged");
  WriteFile(root_ / manifest, valid.substr(0, 20));
  ExpectRefused("sweep merge --out out shard", manifest + ": damaged sweep manifest, not valid JSON: parse error");
  WriteFile(root_ / manifest, std::string(valid).replace(valid.find(R"({"index": 0, "count": 1})"), 24, R"("x")"));
  ExpectRefused("sweep merge --out out shard",
                manifest + ": damaged sweep manifest, 'shard' must be {\"index\": I, \"count\": N}");
  WriteFile(root_ / manifest, std::string(valid).replace(valid.find(R"("cells": {})"), 11, R"("cells": 5)"));
  ExpectRefused("sweep merge --out out shard",
                manifest + ": damaged sweep manifest, 'cells' must be an object of cell ids, got 5");
}

// Options that only a served policy uses are refused with a built-in one, on the command line and
// in a sweep spec (naming the file and key).
TEST_F(RedTeamCliTest, ServedPolicyOptionsWithABuiltInPolicyAreRefused) {
  ExpectRefused("eval --episodes 1 --replan-steps 5 --out out",
                "--replan-steps applies to --policy openpi only, got --policy expert");
  ExpectRefused("eval --episodes 1 --keys libero --out out",
                "--keys applies to --policy openpi only, got --policy expert");
  WriteFile(root_ / "spec.yaml",
            "tasks: [clutter-pick-cube]\nrobots: [gr1t2]\nsplits: [id]\ncameras: [head]\nseeds: [0]\nepisodes: 2\n"
            "policy:\n  name: expert\n  replan_steps: 5\n");
  ExpectRefused("sweep spec.yaml --out out",
                "spec.yaml: policy.replan_steps: applies to policy 'openpi' only, got policy 'expert'");
}

}  // namespace
}  // namespace tavis::tools

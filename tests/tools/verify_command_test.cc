// `tavis verify`: a cell's records re-simulated from its saved actions are identical to what it
// recorded (an expert cell at 20 Hz, a served cell, a sweep's cells, a resumed cell); an edited
// action file or robot file fails naming the episode and field, or the key; a folder that cannot
// be verified exits 2 naming why. Nothing under the verified folder is written.
#include <gtest/gtest.h>
#include <signal.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/batch/remote/policy_server_process.h"
#include "tool_runner.h"

namespace tavis::tools {
namespace {

class VerifyCommand : public TavisCommandTest {
 protected:
  // An expert cell at --expert-hz 20 (it saves its actions) of `episodes` episodes.
  fs::path ExpertCell(const std::string& name, int episodes, const std::string& hz = "20") const {
    const fs::path cell = root_ / name;
    const RunResult run = Run("eval --task clutter-pick-cube --episodes " + std::to_string(episodes) +
                              " --seed 2 --quiet --expert-hz " + hz + " --out " + Quote(cell.string()));
    EXPECT_EQ(run.exit_code, 0) << run.err;
    return cell;
  }
  RunResult Verify(const fs::path& dir, const std::string& options = "") const {
    return Run("verify " + Quote(dir.string()) + " --quiet " + options);
  }
  // A copy of the source tree's configs.
  fs::path ConfigCopy() const {
    const fs::path copy = root_ / "configs";
    fs::copy(fs::path(TAVIS_SOURCE_DIR) / "configs", copy, fs::copy_options::recursive);
    return copy;
  }
};

// A gzip file's text, read by gzip itself.
std::string Gunzipped(const fs::path& path) {
  const fs::path plain = path.parent_path() / (path.stem().string() + ".gunzipped");
  EXPECT_EQ(std::system(("gzip -dc " + Quote(path.string()) + " > " + Quote(plain.string())).c_str()), 0);
  std::string text = ReadText(plain);
  fs::remove(plain);
  return text;
}

// Writes `text` to `path` compressed by gzip itself.
void WriteGzipped(const fs::path& path, const std::string& text) {
  const fs::path plain = path.parent_path() / "text.tmp";
  std::ofstream(plain) << text;
  EXPECT_EQ(std::system(("gzip -n -c " + Quote(plain.string()) + " > " + Quote(path.string())).c_str()), 0);
  fs::remove(plain);
}

// A cell as the versions before compressed actions left it: actions/episode_<i>.csv, plain.
void DecompressActions(const fs::path& cell) {
  for (const auto& entry : fs::directory_iterator(cell / "actions")) {
    if (entry.path().extension() != ".gz") continue;
    std::ofstream(entry.path().parent_path() / entry.path().stem()) << Gunzipped(entry.path());
    fs::remove(entry.path());
  }
}

std::string Replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

TEST_F(VerifyCommand, AnExpertCellAt20HzVerifiesAndNothingInItIsWritten) {
  const fs::path cell = ExpertCell("expert", 4);
  ASSERT_TRUE(fs::exists(cell / "actions" / "episode_3.csv.gz"));
  EXPECT_FALSE(fs::exists(cell / "actions" / "episode_3.csv"));
  const auto before = Snapshot(cell);
  const fs::path report = root_ / "report.json";
  const RunResult run = Verify(cell, "--threads 2 --json " + Quote(report.string()));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("ok   " + cell.string() + ": 4/4 episodes identical"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("1 cells, 1 ok, 0 FAIL"), std::string::npos) << run.out;
  EXPECT_EQ(Snapshot(cell), before);
  const nlohmann::json json = nlohmann::json::parse(ReadText(report));
  EXPECT_EQ(json.at("exit_status"), 0);
  EXPECT_EQ(json.at("cells").at(0).at("outcome"), "ok");
  EXPECT_EQ(json.at("summary").at("identical"), 4);
  // The report must not go into the cell.
  const RunResult inside = Verify(cell, "--json " + Quote((cell / "report.json").string()));
  EXPECT_EQ(inside.exit_code, 2);
  EXPECT_NE(inside.err.find("is inside"), std::string::npos) << inside.err;
}

TEST_F(VerifyCommand, AServedCellVerifies) {
  batch::remote::testing::PolicyServerProcess server(
      {"--horizon", "10", "--action-dim", "19", "--action-scale", "0.001"});
  const fs::path cell = root_ / "served";
  const RunResult served =
      Run("eval --episodes 2 --envs 2 --seed 6 --quiet --image-size 32x24 --policy openpi --server " +
          server.address() + " --out " + Quote(cell.string()));
  ASSERT_EQ(served.exit_code, 0) << served.err;
  // A served cell always keeps its actions, compressed.
  EXPECT_TRUE(fs::exists(cell / "actions" / "episode_0.csv.gz"));
  EXPECT_TRUE(fs::exists(cell / "actions" / "episode_1.csv.gz"));
  const RunResult run = Verify(cell);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("ok   " + cell.string() + ": 2/2 episodes identical"), std::string::npos) << run.out;
  // The plain actions/ of older cells verify the same.
  fs::copy(cell, root_ / "plain", fs::copy_options::recursive);
  DecompressActions(root_ / "plain");
  ASSERT_TRUE(fs::exists(root_ / "plain" / "actions" / "episode_1.csv"));
  const RunResult plain = Verify(root_ / "plain");
  EXPECT_EQ(plain.exit_code, 0) << plain.out << plain.err;
  EXPECT_NE(plain.out.find("2/2 episodes identical"), std::string::npos) << plain.out;
}

TEST_F(VerifyCommand, EveryCellOfASweepVerifies) {
  batch::remote::testing::PolicyServerProcess server(
      {"--horizon", "10", "--action-dim", "19", "--action-scale", "0.001"});
  const fs::path keys = root_ / "small_keys.yaml";
  std::ofstream(keys) << "cameras:\n  head: observation/image\n  fixed: observation/image\nstate: observation/state\n"
                         "prompt: prompt\nimage_layout: hwc\nimage_width: 32\nimage_height: 24\nletterbox: false\n";
  const fs::path spec = root_ / "served.yaml";
  std::ofstream(spec) << "tasks: [clutter-pick-cube]\nrobots: [gr1t2]\nsplits: [id]\ncameras: [head]\n"
                         "seeds: [0, 1]\nepisodes: 2\nenvs: 2\npolicy:\n  name: openpi\n  servers: ["
                      << server.address() << "]\n  keys: " << keys.string() << "\n";
  const fs::path sweep = root_ / "sweep";
  const RunResult swept = Run("sweep " + Quote(spec.string()) + " --out " + Quote(sweep.string()) + " --quiet");
  ASSERT_EQ(swept.exit_code, 0) << swept.out << swept.err;
  const RunResult run = Verify(sweep);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_EQ(Lines(run.out).size(), 3u) << run.out;
  EXPECT_NE(run.out.find("ok   cells/clutter-pick-cube_gr1t2_id_head_openpi_s0: 2/2 episodes identical"),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("2 cells, 2 ok, 0 FAIL"), std::string::npos) << run.out;
}

TEST_F(VerifyCommand, AnInterruptedAndAResumedCellVerify) {
  const std::string cell_args = "eval --task clutter-pick-cube --episodes 8 --seed 3 --quiet --expert-hz 20";
  const fs::path cell = root_ / "cell";
  ASSERT_TRUE(KillWhenLinesAppear(cell_args + " --out " + Quote(cell.string()), cell / "episodes.jsonl", 2, SIGKILL))
      << "the cell finished before it could be interrupted";
  const RunResult partial = Verify(cell);
  ASSERT_EQ(partial.exit_code, 0) << partial.out << partial.err;
  EXPECT_NE(partial.out.find("episodes identical (incomplete: no summary.json)"), std::string::npos) << partial.out;
  ASSERT_EQ(Run(cell_args + " --resume --out " + Quote(cell.string())).exit_code, 0);
  const RunResult whole = Verify(cell);
  ASSERT_EQ(whole.exit_code, 0) << whole.out << whole.err;
  EXPECT_NE(whole.out.find("ok   " + cell.string() + ": 8/8 episodes identical"), std::string::npos) << whole.out;
}

// Episode 12 of this seed is one the expert gives up on (a decision of the policy, which its actions
// do not replay): it is re-simulated up to where it gave up and verifies, as a one-episode cell.
TEST_F(VerifyCommand, AnEpisodeTheExpertGaveUpOnVerifies) {
  const fs::path cell = root_ / "gave_up";
  ASSERT_EQ(Run("eval --task peeking-box --robot reachy2 --episode 12 --seed 0 --quiet --expert-hz 20 --out " +
                Quote(cell.string()))
                .exit_code,
            0);
  ASSERT_NE(ReadText(cell / "episodes.jsonl").find("\"end\":\"gave_up\""), std::string::npos)
      << ReadText(cell / "episodes.jsonl");
  const RunResult run = Verify(cell);
  EXPECT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("ok   " + cell.string() + ": 1/1 episodes identical"), std::string::npos) << run.out;
}

// One episode's grippers never close: it no longer succeeds, and verify names the episode and field.
TEST_F(VerifyCommand, AnEditedActionFileFailsNamingTheEpisodeAndField) {
  const fs::path cell = ExpertCell("expert", 4);
  const std::vector<std::string> records = Lines(ReadText(cell / "episodes.jsonl"));
  int64_t succeeded = -1;
  for (const std::string& line : records) {
    const nlohmann::json record = nlohmann::json::parse(line);
    if (record.at("success").get<bool>()) {
      succeeded = record.at("episode").get<int64_t>();
      break;
    }
  }
  ASSERT_GE(succeeded, 0) << "no successful episode to tamper with";
  const fs::path copy = root_ / "tampered";
  fs::copy(cell, copy, fs::copy_options::recursive);
  const fs::path compressed = copy / "actions" / ("episode_" + std::to_string(succeeded) + ".csv.gz");
  std::string edited;
  for (const std::string& row : Lines(Gunzipped(compressed))) {
    std::vector<std::string> values;
    std::stringstream fields(row);
    for (std::string value; std::getline(fields, value, ',');) values.push_back(value);
    ASSERT_EQ(values.size(), 19u) << row;
    values[17] = values[18] = "-1";  // both grippers open
    for (std::size_t i = 0; i < values.size(); ++i) edited += (i > 0 ? "," : "") + values[i];
    edited += "\n";
  }
  WriteGzipped(compressed, edited);
  const RunResult run = Verify(copy);
  EXPECT_EQ(run.exit_code, 1) << run.out << run.err;
  EXPECT_NE(run.out.find("FAIL " + copy.string() + ": episode " + std::to_string(succeeded) +
                         " field success: true recorded, false re-simulated; 3/4 episodes identical"),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("0 ok, 1 FAIL"), std::string::npos) << run.out;
  // The same edit in an older cell's plain actions fails the same way.
  DecompressActions(copy);
  const RunResult plain = Verify(copy);
  EXPECT_EQ(plain.exit_code, 1) << plain.out << plain.err;
  EXPECT_NE(
      plain.out.find("episode " + std::to_string(succeeded) + " field success: true recorded, false re-simulated"),
      std::string::npos)
      << plain.out;
}

// Two runs on different thread counts write the same records, cell.json and compressed actions,
// byte for byte; only summary.json's run-dependent keys differ, its provenance among them (the
// threads used, the times), which no record comparison reads.
TEST_F(VerifyCommand, ProvenanceDiffersBetweenThreadCountsAndTheRecordsDoNot) {
  std::map<int, fs::path> cells;
  for (const int threads : {1, 2}) {
    cells[threads] = root_ / ("threads" + std::to_string(threads));
    const RunResult run = Run("eval --task clutter-pick-cube --episodes 3 --seed 2 --quiet --expert-hz 20 --threads " +
                              std::to_string(threads) + " --out " + Quote(cells[threads].string()));
    ASSERT_EQ(run.exit_code, 0) << run.err;
  }
  for (const char* file : {"episodes.jsonl", "cell.json", "actions/episode_0.csv.gz", "actions/episode_2.csv.gz"})
    EXPECT_EQ(ReadText(cells[1] / file), ReadText(cells[2] / file)) << file;
  nlohmann::json one = nlohmann::json::parse(ReadText(cells[1] / "summary.json"));
  nlohmann::json two = nlohmann::json::parse(ReadText(cells[2] / "summary.json"));
  EXPECT_EQ(one["provenance"]["machine"]["threads_used"], 1);
  EXPECT_EQ(two["provenance"]["machine"]["threads_used"], 2);
  EXPECT_EQ(one["provenance"]["config_files"], two["provenance"]["config_files"]);
  EXPECT_EQ(one["provenance"]["program"], two["provenance"]["program"]);
  EXPECT_EQ(one["provenance"]["policy"], nlohmann::json({{"label", "expert"}, {"name", "expert"}}));
  EXPECT_GT(one["provenance"]["time"]["wall_s"].get<double>(), 0.0);
  for (const char* run_dependent : {"provenance", "wall_s", "threads", "control_ticks_per_s", "control_ticks"}) {
    one.erase(run_dependent);
    two.erase(run_dependent);
  }
  EXPECT_EQ(one, two);
  EXPECT_EQ(Verify(cells[2]).exit_code, 0);
}

// A submission: a card and its results folder. A valid card's cells are verified; a malformed card
// exits 2 naming the field before any cell is read; a cell of a split the card does not list fails.
TEST_F(VerifyCommand, ASubmissionsCardIsCheckedAndItsCellsVerified) {
  const fs::path submission = root_ / "submission";
  fs::create_directories(submission / "results");
  ExpertCell("submission/results/expert", 2);
  nlohmann::json card = nlohmann::json::parse(R"({
    "format": "tavis-submission/1",
    "model": {"name": "scripted-expert", "version": "1", "policy_family": "scripted"},
    "code": {"url": "https://github.com/example/tavis", "commit": "39cbc19"},
    "checkpoint": {"url": "https://example.org/none"},
    "training": {"steps": 0, "data": ["none: scripted"]},
    "splits": ["id"],
    "results": "results"})");
  std::ofstream(submission / "submission.json") << card.dump(2);
  const fs::path report = root_ / "submission.json";
  const RunResult run = Verify(submission, "--json " + Quote(report.string()));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("submission " + submission.string() + ": scripted-expert 1 (scripted), results results"),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("ok   results/expert: 2/2 episodes identical"), std::string::npos) << run.out;
  EXPECT_EQ(nlohmann::json::parse(ReadText(report))["submission"]["model"]["name"], "scripted-expert");

  card["training"]["steps"] = "many";
  std::ofstream(submission / "submission.json") << card.dump(2);
  const RunResult bad = Verify(submission);
  EXPECT_EQ(bad.exit_code, 2) << bad.out << bad.err;
  EXPECT_NE(bad.err.find((submission / "submission.json").string() +
                         ": training.steps: must be an integer >= 0, got \"many\""),
            std::string::npos)
      << bad.err;
  EXPECT_EQ(bad.out.find("results/expert"), std::string::npos) << bad.out;

  card["training"]["steps"] = 100;
  card["splits"] = {"ood-spatial"};
  std::ofstream(submission / "submission.json") << card.dump(2);
  const RunResult other = Verify(submission);
  EXPECT_EQ(other.exit_code, 1) << other.out << other.err;
  EXPECT_NE(other.out.find("FAIL results/expert: does not match the submission card: split id is not among the "
                           "card's splits"),
            std::string::npos)
      << other.out;
}

// A cell an older version wrote lacks the fields added since (failure events, motion quality):
// they are named and not compared. Written by this version, a missing field is a difference.
TEST_F(VerifyCommand, FieldsAnOlderVersionDidNotRecordAreNamedNotCompared) {
  const fs::path cell = ExpertCell("expert", 2);
  std::string records = ReadText(cell / "episodes.jsonl");
  std::string stripped;
  std::istringstream lines(records);
  for (std::string line; std::getline(lines, line);) {
    nlohmann::json record = nlohmann::json::parse(line);
    ASSERT_TRUE(record.contains("motion")) << line;
    record.erase("motion");
    stripped += record.dump() + "\n";
  }
  std::ofstream(cell / "episodes.jsonl") << stripped;
  const RunResult same_version = Verify(cell);
  EXPECT_EQ(same_version.exit_code, 1) << same_version.out << same_version.err;
  EXPECT_NE(same_version.out.find("motion"), std::string::npos) << same_version.out;

  nlohmann::json cell_json = nlohmann::json::parse(ReadText(cell / "cell.json"));
  cell_json["identity"]["program_version"] = "an older version";
  std::ofstream(cell / "cell.json") << cell_json.dump(2) << "\n";
  const RunResult older = Verify(cell);
  EXPECT_EQ(older.exit_code, 0) << older.out << older.err;
  EXPECT_NE(older.out.find("2/2 episodes identical (not in the older records, not compared: motion)"),
            std::string::npos)
      << older.out;
}

TEST_F(VerifyCommand, AChangedRobotFileFailsNamingTheKey) {
  const fs::path cell = ExpertCell("expert", 2);
  const fs::path configs = ConfigCopy();
  const fs::path robot = configs / "robots" / "gr1t2.yaml";
  const std::string original = ReadText(robot);
  std::ofstream(robot) << Replaced(original, "effort_limit: 30.0, position_gain: 60.0",
                                   "effort_limit: 30.0, position_gain: 61.0");
  const RunResult run = Verify(cell, "--config-dir " + Quote(configs.string()));
  EXPECT_EQ(run.exit_code, 1) << run.out << run.err;
  EXPECT_NE(run.out.find("FAIL " + cell.string() +
                         ": identity.robot_config.actuators.arm.position_gain: 60.0 recorded, 61.0 now"),
            std::string::npos)
      << run.out;
  // The unchanged copy verifies.
  std::ofstream(robot) << original;
  EXPECT_EQ(Verify(cell, "--config-dir " + Quote(configs.string())).exit_code, 0);
}

TEST_F(VerifyCommand, WhatCannotBeVerifiedExits2NamingWhy) {
  const fs::path empty = root_ / "empty";
  fs::create_directories(empty);
  const RunResult none = Verify(empty);
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_NE(none.err.find("no cell found under " + empty.string()), std::string::npos) << none.err;

  const fs::path plain = ExpertCell("expert60", 2, "60");
  const RunResult no_actions = Verify(plain);
  EXPECT_EQ(no_actions.exit_code, 2) << no_actions.out;
  EXPECT_NE(no_actions.out.find("skip " + plain.string() +
                                ": cannot verify: no actions: policy 'expert' at expert_hz 60 saves none"),
            std::string::npos)
      << no_actions.out;
  const RunResult skipped = Verify(plain, "--skip-unverifiable");
  EXPECT_EQ(skipped.exit_code, 0) << skipped.out;
  EXPECT_NE(skipped.out.find("1 without actions (skipped)"), std::string::npos) << skipped.out;
  EXPECT_NE(skipped.out.find("without actions: " + plain.string()), std::string::npos) << skipped.out;

  const fs::path cell = ExpertCell("expert", 2);
  const std::string settings = ReadText(cell / "cell.json");
  std::ofstream(cell / "cell.json") << settings.substr(0, settings.size() / 2);
  const RunResult damaged = Verify(cell);
  EXPECT_EQ(damaged.exit_code, 2);
  EXPECT_NE(damaged.out.find((cell / "cell.json").string() + ": not valid JSON"), std::string::npos) << damaged.out;
  EXPECT_NE(damaged.out.find("1 unreadable"), std::string::npos) << damaged.out;

  // A usage error is not a difference either: 2, naming the bad value, never 1.
  const RunResult usage = Verify(plain, "--threads -1");
  EXPECT_EQ(usage.exit_code, 2);
  EXPECT_NE(usage.err.find("--threads: must be an integer from 0 to 1024, got '-1'"), std::string::npos) << usage.err;
}

}  // namespace
}  // namespace tavis::tools

// `tavis demos` with the rest of the program: a dataset's video frame is the image `tavis render`
// draws of the same tick, its GALT table equals the one `tavis eval` reports for the same episodes,
// and a recording killed mid-way and resumed ends byte-identical to an uninterrupted one.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/image_io.h"
#include "tests/batch/dataset/pyav_video.h"
#include "tool_runner.h"

namespace tavis::tools {
namespace {

using DemosPipeline = TavisCommandTest;

nlohmann::json ReadJson(const fs::path& path) { return nlohmann::json::parse(ReadText(path)); }

// The pixels of the image `tavis render` wrote at `path`.
batch::dataset::testing::RgbFrame Png(const fs::path& path) { return render::ReadPng(path.string()).pixels; }

// The files of a dataset folder (its Snapshot) by their path inside it, without the run's report.
std::map<std::string, std::string> DatasetFiles(const std::map<std::string, std::string>& snapshot,
                                                const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& [path, text] : snapshot) {
    if (path.find("tavis_demos.json") == std::string::npos) files[path.substr(dir.string().size())] = text;
  }
  return files;
}

TEST_F(DemosPipeline, TheFrameLeRobotLooksUpIsTheImageRenderedAfterThatAction) {
  const fs::path dataset_dir = root_ / "dataset";
  ASSERT_EQ(
      Run("demos --task clutter-pick-cube --episodes 1 --fps 60 --image-size 128x96 --cameras head --quiet --out " +
          Quote(dataset_dir.string()))
          .exit_code,
      0);
  // Frame k holds the observation after action k: the scene after k + 1 control ticks.
  constexpr int kFrame = 59;
  const RunResult render = Run("render --task clutter-pick-cube --seed 0 --episode 0 --width 128 --height 96 --steps " +
                               std::to_string(kFrame + 1) + " --out " + Quote((root_ / "views").string()));
  ASSERT_EQ(render.exit_code, 0) << render.err;
  const batch::dataset::testing::PyAvReport report = batch::dataset::testing::CheckVideoWithPyAv(
      (dataset_dir / "videos/observation.images.OBS_HEAD/chunk-000/file-000.mp4").string(), 60,
      {{0.0, kFrame}, {0.0, 0}}, root_.string());
  ASSERT_TRUE(report.frames[0] && report.frames[1]) << report.stream.dump();
  const batch::dataset::testing::RgbFrame rendered =
      Png(root_ / "views" / ("tick" + std::to_string(kFrame + 1) + "_head.png"));
  const double same = batch::dataset::testing::Psnr(*report.frames[0], rendered);
  const double earlier = batch::dataset::testing::Psnr(*report.frames[1], rendered);
  // H.264 at crf 23 keeps about 31-32 dB of these small frames, about what separates neighbouring
  // ticks, so this checks the frame to within a tick or two (an off-by-one is not resolved); the
  // scene a second earlier is below 15 dB.
  EXPECT_GE(same, 30.0) << "frame " << kFrame << " against the render of tick " << kFrame + 1;
  EXPECT_LT(earlier, same - 10.0) << "the first frame must not match as well: the head has moved";
}

TEST_F(DemosPipeline, GaltTableOfTheDatasetEqualsTheCellsForTheSameEpisodes) {
  const std::string episodes = "--task clutter-pick-cube --robot gr1t2 --episodes 6 --seed 3";
  const RunResult cell = Run("eval " + episodes + " --quiet --out " + Quote((root_ / "cell").string()));
  ASSERT_EQ(cell.exit_code, 0) << cell.err;
  const nlohmann::json summary = ReadJson(root_ / "cell" / "summary.json");
  ASSERT_EQ(summary["n_successful"], 6) << "the comparison needs every episode in the dataset";

  const RunResult demos =
      Run("demos " + episodes + " --cameras '' --quiet --out " + Quote((root_ / "dataset").string()));
  ASSERT_EQ(demos.exit_code, 0) << demos.err;
  const RunResult galt = Run("galt --dataset " + Quote((root_ / "dataset").string()) + " --json-out " +
                             Quote((root_ / "table.json").string()));
  ASSERT_EQ(galt.exit_code, 0) << galt.err;
  // Episode by episode: the dataset's GALT lines against the cell's episodes.jsonl.
  const std::vector<std::string> cell_lines = Lines(ReadText(root_ / "cell" / "episodes.jsonl"));
  std::vector<nlohmann::json> dataset_lines;
  for (const std::string& line : Lines(galt.out)) {
    if (line.front() == '{') dataset_lines.push_back(nlohmann::json::parse(line));
  }
  ASSERT_EQ(dataset_lines.size(), cell_lines.size());
  for (std::size_t i = 0; i < cell_lines.size(); ++i) {
    const nlohmann::json record = nlohmann::json::parse(cell_lines[i]);
    EXPECT_EQ(dataset_lines[i]["episode"], record["episode"]);
    EXPECT_EQ(dataset_lines[i]["galt_s"], record["galt_s"]) << "episode " << i;
    EXPECT_EQ(dataset_lines[i]["reason"], record["galt_reason"]) << "episode " << i;
  }
  const nlohmann::json table = ReadJson(root_ / "table.json");
  ASSERT_EQ(table["rows"].size(), 2U);
  // 60 Hz: every control tick's action, as the cell's GALT; 20 Hz: every third, as its policy-rate GALT.
  for (const auto& [row, cell_galt] :
       {std::pair{table["rows"][0], summary["galt"]}, std::pair{table["rows"][1], summary["galt_policy_rate"]}}) {
    EXPECT_EQ(row["n_episodes"], cell_galt["n_episodes"]);
    EXPECT_EQ(row["n_valid"], cell_galt["n_valid"]);
    EXPECT_EQ(row["mean_s"], cell_galt["mean_s"]) << row.dump();
    EXPECT_EQ(row["median_s"], cell_galt["median_s"]) << row.dump();
  }
}

TEST_F(DemosPipeline, KilledAndResumedRecordingEqualsAnUninterruptedOne) {
  const std::string args =
      "demos --task clutter-pick-cube --episodes 16 --fps 20 --image-size 64x48 --cameras head,left_wrist --quiet";
  ASSERT_EQ(Run(args + " --out " + Quote((root_ / "whole").string())).exit_code, 0);

  // Killed once the spool holds a few kept episodes (bounded: the whole run takes seconds).
  const fs::path out = root_ / "resumed";
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const std::string command =
        Quote(TAVIS_BINARY) + " " + args + " --threads 2 --out " + Quote(out.string()) + " >/dev/null 2>&1";
    execl("/bin/sh", "sh", "-c", ("exec " + command).c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!fs::exists(out / ".tavis_spool" / "episode_000003" / "episode.json") &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  kill(child, SIGKILL);
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the recording finished before it could be killed";
  EXPECT_TRUE(fs::exists(out / "INCOMPLETE"));
  EXPECT_FALSE(fs::exists(out / "meta" / "info.json")) << "an interrupted dataset must not look finished";

  const RunResult refused = Run(args + " --out " + Quote(out.string()));
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_NE(refused.err.find("--resume"), std::string::npos) << refused.err;
  const RunResult other = Run(args + " --seed 9 --resume --out " + Quote(out.string()));
  EXPECT_EQ(other.exit_code, 1);
  EXPECT_NE(other.err.find("seed 0 -> 9"), std::string::npos) << other.err;

  const RunResult resumed = Run(args + " --threads 1 --resume --out " + Quote(out.string()));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_GE(ReadJson(out / "tavis_demos.json")["resumed_episodes"].get<int>(), 4);
  EXPECT_FALSE(fs::exists(out / "INCOMPLETE"));
  EXPECT_FALSE(fs::exists(out / ".tavis_spool"));
  const std::map<std::string, std::string> whole = DatasetFiles(Snapshot(root_ / "whole"), root_ / "whole");
  std::map<std::string, std::string> again = DatasetFiles(Snapshot(out), out);
  EXPECT_EQ(whole.size(), again.size());
  for (const auto& [path, text] : whole) EXPECT_TRUE(again.count(path) && again[path] == text) << path << " differs";
}

// --max-attempts ran out (multi-shelf-scan's expert fails one of its first 12 episodes with seed
// 0): the kept episodes stay in the spool and --resume with more attempts finishes the dataset,
// equal to an uninterrupted run with those attempts, its failure counts included.
TEST_F(DemosPipeline, RecordingStrandedByMaxAttemptsIsFinishedByAResumeWithMoreAttempts) {
  const std::string args =
      "demos --task multi-shelf-scan --episodes 12 --fps 20 --image-size 64x48 --cameras head --quiet";
  const fs::path whole = root_ / "whole", stranded = root_ / "stranded";
  ASSERT_EQ(Run(args + " --max-attempts 20 --out " + Quote(whole.string())).exit_code, 0);
  const nlohmann::json whole_task = ReadJson(whole / "tavis_demos.json")["tasks"][0];
  ASSERT_LE(whole_task["attempts"].get<int>(), 20);
  ASSERT_GT(whole_task["attempts"].get<int>(), 12) << "the premise: an episode among the first 12 fails";

  const RunResult ran_out = Run(args + " --max-attempts 12 --out " + Quote(stranded.string()));
  ASSERT_EQ(ran_out.exit_code, 1);
  EXPECT_NE(ran_out.err.find("--resume with a larger --max-attempts finishes the dataset"), std::string::npos)
      << ran_out.err;
  EXPECT_TRUE(fs::exists(stranded / "INCOMPLETE"));
  EXPECT_TRUE(fs::exists(stranded / ".tavis_spool" / "episode_000000" / "episode.json"));

  const RunResult resumed = Run(args + " --max-attempts 20 --threads 1 --resume --out " + Quote(stranded.string()));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  const nlohmann::json report = ReadJson(stranded / "tavis_demos.json");
  EXPECT_GE(report["resumed_episodes"].get<int>(), 1);
  EXPECT_EQ(report["tasks"][0], whole_task) << "written, attempts and failures as without the interruption";
  EXPECT_FALSE(fs::exists(stranded / "INCOMPLETE"));
  EXPECT_FALSE(fs::exists(stranded / ".tavis_spool"));
  const std::map<std::string, std::string> expected = DatasetFiles(Snapshot(whole), whole),
                                           got = DatasetFiles(Snapshot(stranded), stranded);
  EXPECT_EQ(expected.size(), got.size());
  for (const auto& [path, text] : expected) EXPECT_TRUE(got.count(path) && got.at(path) == text) << path << " differs";
}

// A damaged spool record is named with what is wrong, not as a bare library message.
TEST_F(DemosPipeline, DamagedSpoolRecordIsNamed) {
  const std::string args =
      "demos --task multi-shelf-scan --episodes 12 --fps 20 --image-size 64x48 --cameras head --quiet";
  const fs::path out = root_ / "stranded";
  ASSERT_EQ(Run(args + " --max-attempts 12 --out " + Quote(out.string())).exit_code, 1);
  const fs::path record = out / ".tavis_spool" / "episode_000000" / "episode.json";
  nlohmann::json damaged = ReadJson(record);
  damaged["frames"] = "many";
  std::ofstream(record) << damaged.dump();
  const RunResult resumed = Run(args + " --max-attempts 20 --resume --out " + Quote(out.string()));
  EXPECT_EQ(resumed.exit_code, 1);
  EXPECT_NE(resumed.err.find(record.string() + ": damaged spool file, \"frames\" is \"many\""), std::string::npos)
      << resumed.err;
  EXPECT_EQ(resumed.err.find("json.exception"), std::string::npos) << resumed.err;

  std::ofstream(out / ".tavis_spool" / "progress.json") << "{\"settings\": ";
  const RunResult truncated = Run(args + " --max-attempts 20 --resume --out " + Quote(out.string()));
  EXPECT_EQ(truncated.exit_code, 1);
  EXPECT_NE(
      truncated.err.find((out / ".tavis_spool" / "progress.json").string() + ": damaged spool file, not valid JSON"),
      std::string::npos)
      << truncated.err;
  EXPECT_TRUE(fs::exists(record)) << "nothing already recorded is lost";
}

}  // namespace
}  // namespace tavis::tools

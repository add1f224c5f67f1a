// The progress of eval and demos: its text (rate, ETA), plain lines when stderr is not a terminal,
// a rewritten status line when it is, and what the real program writes to a log file.
#include "tools/progress_reporter.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/batch/remote/policy_server_process.h"
#include "tool_runner.h"

namespace tavis::tools {
namespace {

using Time = std::chrono::steady_clock::time_point;

// What a reporter wrote into a temporary FILE*.
std::string Contents(std::FILE* file) {
  std::fflush(file);
  std::rewind(file);
  std::string text;
  for (int c; (c = std::fgetc(file)) != EOF;) text += static_cast<char>(c);
  return text;
}

// A reporter on a fake clock that the test moves.
struct FakeClockReporter {
  explicit FakeClockReporter(ProgressReporter::Style style)
      : file(std::tmpfile()), reporter(file, style, [this] { return now; }) {}
  ~FakeClockReporter() { std::fclose(file); }
  void Advance(double seconds) {
    now += std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(seconds));
  }
  std::FILE* file;
  Time now{};
  ProgressReporter reporter;
};

TEST(FormatProgress, RateAndEta) {
  EXPECT_EQ(FormatProgress(24, 96, 24, 12.0), "24/96 episodes, 2.0 episodes/s, ETA 36s");
  EXPECT_EQ(FormatProgress(10, 1000, 10, 5.0), "10/1000 episodes, 2.0 episodes/s, ETA 8m15s");
  EXPECT_EQ(FormatProgress(96, 96, 96, 48.0), "96/96 episodes, 2.0 episodes/s, ETA 0s");
  EXPECT_EQ(FormatProgress(0, 96, 0, 0.0), "0/96 episodes, 0.0 episodes/s, ETA -");
}

// A resumed run: the episodes done before it do not count into its rate.
TEST(FormatProgress, RateCountsOnlyThisRunsEpisodes) {
  EXPECT_EQ(FormatProgress(60, 100, 10, 10.0), "60/100 episodes, 1.0 episodes/s, ETA 40s");
}

TEST(ProgressReporter, PlainLinesOnePerTenthWithoutCarriageReturns) {
  FakeClockReporter fake(ProgressReporter::Style::kPlainLines);
  for (int done = 1; done <= 40; ++done) {
    fake.Advance(0.5);
    fake.reporter.Update("", done, 40);
  }
  const std::string text = Contents(fake.file);
  EXPECT_EQ(text.find('\r'), std::string::npos) << text;
  const std::vector<std::string> lines = Lines(text);
  // The first call (1/40) starts the clock; then a line at each tenth, 4/40 .. 40/40.
  ASSERT_EQ(lines.size(), 10u) << text;
  EXPECT_EQ(lines.front(), "  4/40 episodes, 2.0 episodes/s, ETA 18s");
  EXPECT_EQ(lines[2], "  12/40 episodes, 2.0 episodes/s, ETA 14s");
  EXPECT_EQ(lines.back(), "  40/40 episodes, 2.0 episodes/s, ETA 0s");
}

TEST(ProgressReporter, AResumedRunCountsItsRateFromItsFirstUpdate) {
  FakeClockReporter fake(ProgressReporter::Style::kPlainLines);
  fake.reporter.Update("", 50, 100);  // resumed after 50 episodes
  for (int done = 51; done <= 100; ++done) {
    fake.Advance(1.0);
    fake.reporter.Update("", done, 100);
  }
  const std::vector<std::string> lines = Lines(Contents(fake.file));
  ASSERT_EQ(lines.size(), 5u);
  EXPECT_EQ(lines.front(), "  60/100 episodes, 1.0 episodes/s, ETA 40s");
}

TEST(ProgressReporter, ANewLabelStartsANewCount) {
  FakeClockReporter fake(ProgressReporter::Style::kPlainLines);
  fake.reporter.Update("task-a", 0, 2);
  fake.Advance(10.0);
  fake.reporter.Update("task-a", 2, 2);
  fake.reporter.Update("task-b", 0, 2);
  fake.Advance(1.0);
  fake.reporter.Update("task-b", 1, 2);
  const std::vector<std::string> lines = Lines(Contents(fake.file));
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0], "  task-a: 2/2 episodes, 0.2 episodes/s, ETA 0s");
  EXPECT_EQ(lines[1], "  task-b: 1/2 episodes, 1.0 episodes/s, ETA 1s");
}

TEST(ProgressReporter, StatusLineIsRewrittenInPlaceAtMostFourTimesASecond) {
  FakeClockReporter fake(ProgressReporter::Style::kStatusLine);
  for (int done = 1; done <= 10; ++done) {
    fake.Advance(0.1);
    fake.reporter.Update("", done, 10);
  }
  const std::string text = Contents(fake.file);
  // Drawn at 0.1 s (first), 0.4, 0.7, 1.0 (last, always drawn).
  EXPECT_EQ(std::count(text.begin(), text.end(), '\r'), 4) << text;
  EXPECT_EQ(text.back(), '\n');
  EXPECT_NE(text.find("\r\033[K  10/10 episodes, 10.0 episodes/s, ETA 0s\n"), std::string::npos) << text;
}

TEST(ProgressReporter, StyleFollowsWhetherTheFileIsATerminal) {
  std::FILE* file = std::tmpfile();
  EXPECT_EQ(ProgressReporter::StyleFor(file), ProgressReporter::Style::kPlainLines);
  std::fclose(file);
}

// The real program with stderr in a file, as under Slurm or `2> log`.
using ProgressInLogs = TavisCommandTest;

TEST_F(ProgressInLogs, EvalWritesPlainProgressLinesWithRateAndEta) {
  const RunResult run = Run("eval --episodes 4 --envs 2 --threads 2 --out " + Quote((root_ / "cell").string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.err.find('\r'), std::string::npos) << run.err;
  const std::vector<std::string> lines = Lines(run.err);
  ASSERT_FALSE(lines.empty());
  EXPECT_NE(lines.back().find("4/4 episodes, "), std::string::npos) << run.err;
  EXPECT_NE(lines.back().find(" episodes/s, ETA 0s"), std::string::npos) << run.err;
}

// The rate of the last progress line ("4/4 episodes, R episodes/s, ETA 0s").
double LastRate(const std::string& err) {
  const std::vector<std::string> lines = Lines(err);
  if (lines.empty()) return -1.0;
  const std::string& last = lines.back();
  const std::size_t comma = last.find("episodes, ");
  return comma == std::string::npos ? -1.0 : std::stod(last.substr(comma + 10));
}

// A served cell runs its slots lock-step, so its episodes end together: a rate timed from the
// first of them to end divided the batch by microseconds ("1671.6 episodes/s" for a cell of
// 0.6 episodes/s). Timed from the run's start it is at most what the cell's wall time says.
TEST_F(ProgressInLogs, AServedCellsRateCountsFromTheStartOfTheRun) {
  batch::remote::testing::PolicyServerProcess server(
      {"--horizon", "10", "--action-dim", "19", "--action-scale", "0.001"});
  const fs::path dir = root_ / "served";
  const RunResult run = Run("eval --episodes 4 --envs 4 --seed 6 --image-size 32x24 --policy openpi --server " +
                            server.address() + " --out " + Quote(dir.string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json summary = nlohmann::json::parse(ReadText(dir / "summary.json"));
  const double wall_rate = 4.0 / summary.at("wall_s").get<double>();
  const double shown = LastRate(run.err);
  // The run starts after the cell has made its env and asked the server for its metadata, so the
  // rate shown is a little above the cell's own; many times it is the burst.
  EXPECT_GT(shown, 0.0) << run.err;
  EXPECT_LT(shown, 1.5 * wall_rate) << run.err << "\nthe cell's rate: " << wall_rate;
}

TEST_F(ProgressInLogs, DemosWritesPlainProgressLinesPerTask) {
  const RunResult run = Run("demos --episodes 2 --envs 1 --fps 20 --image-size 64x48 --cameras head --out " +
                            Quote((root_ / "dataset").string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.err.find('\r'), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("clutter-pick-cube (written): 2/2 episodes, "), std::string::npos) << run.err;
  EXPECT_NE(run.err.find(" episodes/s, ETA 0s"), std::string::npos) << run.err;
}

TEST_F(ProgressInLogs, QuietWritesNoProgress) {
  const RunResult run = Run("eval --episodes 2 --envs 2 --quiet --out " + Quote((root_ / "cell").string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.err.find("episodes/s"), std::string::npos) << run.err;
}

}  // namespace
}  // namespace tavis::tools

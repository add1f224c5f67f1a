#include "batch/cell/evaluation_cell.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cstddef>
#include <stdexcept>
#include <string>

#include "configs/yaml_reader.h"

namespace tavis::batch::cell {
namespace {

EvaluationCellConfig SmallCell(uint64_t seed = 3, int envs = 3) {
  EvaluationCellConfig config;
  config.task = "clutter-pick-cube";
  config.robot = "gr1t2";
  config.split = scenarios::Split::kId;
  config.policy = "expert";
  config.episodes = 6;
  config.envs = envs;
  config.seed = seed;
  config.keep_actions = true;  // the tests compare every control tick's action
  config.config_dir = TAVIS_CONFIG_DIR;
  return config;
}

CellResult RunWithThreads(const EvaluationCellConfig& config, std::size_t threads) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  return RunEvaluationCell(config);
}

// Every per-episode field, and the full action logs compared exactly (bitwise equal doubles).
void ExpectSameRecords(const CellResult& a, const CellResult& b, const std::string& what) {
  ASSERT_EQ(a.episodes.size(), b.episodes.size()) << what;
  EXPECT_EQ(a.successes, b.successes) << what;
  EXPECT_EQ(a.control_ticks, b.control_ticks) << what;
  for (std::size_t i = 0; i < a.episodes.size(); ++i) {
    const EpisodeRecord& x = a.episodes[i];
    const EpisodeRecord& y = b.episodes[i];
    EXPECT_EQ(x.episode, y.episode) << what << ", episode " << i;
    EXPECT_EQ(x.success, y.success) << what << ", episode " << i;
    EXPECT_EQ(x.end, y.end) << what << ", episode " << i;
    EXPECT_EQ(x.length_steps, y.length_steps) << what << ", episode " << i;
    EXPECT_EQ(x.length_control_ticks, y.length_control_ticks) << what << ", episode " << i;
    ASSERT_EQ(x.actions.size(), y.actions.size()) << what << ", episode " << i;
    for (std::size_t t = 0; t < x.actions.size(); ++t) {
      ASSERT_EQ(x.actions[t], y.actions[t]) << what << ", episode " << i << ", control tick " << t;
    }
  }
}

void ExpectWellFormed(const CellResult& result) {
  const EvaluationCellConfig& config = result.config;
  ASSERT_EQ(static_cast<int>(result.episodes.size()), config.episodes);
  int successes = 0;
  int64_t ticks = 0;
  for (std::size_t i = 0; i < result.episodes.size(); ++i) {
    const EpisodeRecord& record = result.episodes[i];
    EXPECT_EQ(record.episode, static_cast<int64_t>(i));
    EXPECT_NE(record.end, engine::EpisodeEnd::kRunning);
    EXPECT_EQ(record.success, record.end == engine::EpisodeEnd::kSuccess);
    EXPECT_GT(record.length_control_ticks, 0);
    EXPECT_EQ(static_cast<int>(record.actions.size()), record.length_control_ticks);
    // 20 Hz policy steps from 60 Hz control ticks, rounded up.
    EXPECT_EQ(record.length_steps, (record.length_control_ticks + 2) / 3);
    // GALT is computed for successful episodes only, and the expert grasps in each of them.
    EXPECT_EQ(record.galt.has_value(), record.success);
    if (record.galt) {
      EXPECT_NE(record.galt->reason, kinematics::GaltReason::kNoGrasp);
    }
    successes += record.success ? 1 : 0;
    ticks += record.length_control_ticks;
  }
  EXPECT_EQ(result.successes, successes);
  EXPECT_EQ(result.control_ticks, ticks);
  EXPECT_GT(result.wall_s, 0.0);
  EXPECT_DOUBLE_EQ(result.galt_fps, 60.0);  // the expert acts at the control rate
}

TEST(EvaluationCell, RecordsAreIdenticalForOneAndTwoThreads) {
  const EvaluationCellConfig config = SmallCell();
  const CellResult one = RunWithThreads(config, 1);
  const CellResult two = RunWithThreads(config, 2);
  ExpectWellFormed(one);
  ExpectSameRecords(one, two, "1 vs 2 threads");
}

TEST(EvaluationCell, RecordsAreIdenticalForOneAndFourEnvSlots) {
  const CellResult one = RunWithThreads(SmallCell(3, 1), 2);
  const CellResult four = RunWithThreads(SmallCell(3, 4), 2);
  ExpectWellFormed(one);
  ExpectWellFormed(four);
  ExpectSameRecords(one, four, "1 vs 4 env slots");
}

TEST(EvaluationCell, SameSeedRepeatsAndOtherSeedDiffers) {
  const CellResult first = RunWithThreads(SmallCell(3), 2);
  const CellResult again = RunWithThreads(SmallCell(3), 2);
  ExpectSameRecords(first, again, "two runs with seed 3");

  const CellResult other = RunWithThreads(SmallCell(4), 2);
  ExpectWellFormed(other);
  int differing = 0;
  for (std::size_t i = 0; i < first.episodes.size(); ++i) {
    differing += first.episodes[i].actions != other.episodes[i].actions ? 1 : 0;
  }
  // Each episode's layout comes from (seed, episode): another seed gives other layouts and so
  // other expert actions, episode by episode.
  EXPECT_EQ(differing, static_cast<int>(first.episodes.size()));
}

TEST(EvaluationCell, RenderedCamerasLeaveRecordsUnchangedAndRenderEveryPolicyStep) {
  EvaluationCellConfig plain = SmallCell(3, 2);
  plain.episodes = 3;
  EvaluationCellConfig rendered = plain;
  rendered.render_cameras = {"head", "left_wrist", "right_wrist"};
  rendered.image_width = 32;
  rendered.image_height = 24;
  const CellResult without = RunWithThreads(plain, 2);
  const CellResult with = RunWithThreads(rendered, 2);
  ExpectWellFormed(with);
  ExpectSameRecords(without, with, "without vs with rendering");
  // A built-in policy's cell runs per slot, rendered or not: each slot renders at its own ticks.
  EXPECT_TRUE(RunsPerSlot(plain));
  EXPECT_TRUE(without.per_slot);
  EXPECT_TRUE(RunsPerSlot(rendered));
  EXPECT_TRUE(with.per_slot);
  EXPECT_EQ(without.rendered_images, 0) << "the expert needs no images: nothing is rendered";
  EXPECT_TRUE(without.rendered_cameras.empty());
  EXPECT_EQ(with.rendered_cameras, rendered.render_cameras);
  // One render per 20 Hz policy step of every episode (control ticks 0, 3, 6, ...), 3 cameras.
  int64_t policy_steps = 0;
  for (const EpisodeRecord& record : with.episodes) policy_steps += record.length_steps;
  EXPECT_EQ(with.rendered_images, 3 * policy_steps);
}

template <typename Error>
void ExpectErrorNaming(const EvaluationCellConfig& config, const std::string& needle) {
  try {
    RunEvaluationCell(config);
    FAIL() << "expected an error naming '" << needle << "'";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(EvaluationCell, BadSettingsThrowNamingTheValue) {
  EvaluationCellConfig config = SmallCell();
  config.episodes = 0;
  ExpectErrorNaming<output::SettingError>(config, "episodes must be at least 1, got 0");
  config.episodes = -4;
  ExpectErrorNaming<std::invalid_argument>(config, "got -4");

  config = SmallCell();
  config.envs = 0;
  ExpectErrorNaming<output::SettingError>(config, "envs must be at least 1, got 0");

  config = SmallCell();
  config.task = "clutter-pick-sphere";
  ExpectErrorNaming<std::invalid_argument>(config, "clutter-pick-sphere");

  config = SmallCell();
  config.render_cameras = {"head", "chest"};
  ExpectErrorNaming<std::invalid_argument>(config, "unknown camera 'chest'");
  config.render_cameras = {"head"};
  config.image_width = 0;
  config.image_height = 480;
  ExpectErrorNaming<output::SettingError>(config, "image_width and image_height must be given together");
  config.image_width = -4;
  ExpectErrorNaming<std::invalid_argument>(config, "image size -4x480");

  config = SmallCell();
  config.robot = "robby";
  ExpectErrorNaming<configs::ConfigError>(config, "robby");

  config = SmallCell();
  config.policy = "oracle";
  ExpectErrorNaming<std::invalid_argument>(config, "oracle");
}

// A resumed cell: its plan continued from an episode runs the rest of the cell, with the records
// those episodes have in the whole cell.
TEST(EvaluationCell, APlanContinuedFromAnEpisodeRecordsTheRestOfTheCell) {
  EvaluationCellConfig config = SmallCell(3, 2);
  config.episodes = 3;
  const CellResult whole = RunWithThreads(config, 2);
  CellPlan plan = PlanCell(config);
  plan.ContinueFrom(1);
  const CellResult rest = RunEvaluationCell(plan);
  ASSERT_EQ(rest.episodes.size(), 2u);
  EXPECT_EQ(rest.envs, 2);
  for (std::size_t i = 0; i < rest.episodes.size(); ++i) {
    const EpisodeRecord& x = whole.episodes[i + 1];
    const EpisodeRecord& y = rest.episodes[i];
    EXPECT_EQ(y.episode, x.episode);
    EXPECT_EQ(y.end, x.end);
    EXPECT_EQ(y.length_control_ticks, x.length_control_ticks);
    EXPECT_EQ(y.actions, x.actions) << "episode " << y.episode;
  }
  plan.ContinueFrom(3);
  EXPECT_TRUE(RunEvaluationCell(plan).episodes.empty()) << "a complete cell runs nothing";
}

}  // namespace
}  // namespace tavis::batch::cell

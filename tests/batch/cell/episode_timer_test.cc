// Every episode of a cell timed (episode_timer.h) on either schedule: its parts are non-negative
// and add up to at most its span; per slot to the span itself, lock-step (where every interval is
// shared among the live episodes) to no more than the loop's time over all episodes.
#include "batch/cell/episode_timer.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <string>
#include <vector>

#include "batch/cell/evaluation_cell.h"

namespace tavis::batch::cell {
namespace {

// The expert on clutter-pick-cube with the head camera rendered, three episodes on two slots.
EvaluationCellConfig RenderedExpertCell() {
  EvaluationCellConfig config;
  config.episodes = 3;
  config.envs = 2;
  config.seed = 5;
  config.render_cameras = {"head"};
  config.image_width = 64;
  config.image_height = 48;
  config.config_dir = TAVIS_CONFIG_DIR;
  return config;
}

// A sink that needs the common tick: the cell runs lock-step.
class LockStepSink : public EpisodeSink {};

double MeasuredParts(const EpisodeTimes& times) {
  double sum = 0.0;
  for (double seconds : times.parts) sum += seconds;
  return sum;
}

TEST(EpisodeTimer, EveryEpisodeIsTimedWithItsPartsAddingUpToAtMostItsSpanOnEitherSchedule) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
  for (const bool lock_step : {false, true}) {
    const std::string label = lock_step ? "lock-step" : "per slot";
    LockStepSink sink;
    const CellSinks sinks = [&sink](const VecEnv&, const std::vector<std::string>&) {
      return std::vector<EpisodeSink*>{&sink};
    };
    const CellResult result = RunEvaluationCell(RenderedExpertCell(), nullptr, nullptr, lock_step ? sinks : nullptr);
    ASSERT_EQ(result.per_slot, !lock_step) << label;
    ASSERT_EQ(result.episodes.size(), 3u) << label;
    double all_parts = 0.0;
    for (const EpisodeRecord& record : result.episodes) {
      const std::string episode = label + ", episode " + std::to_string(record.episode);
      ASSERT_TRUE(record.times.has_value()) << episode;
      const EpisodeTimes& times = *record.times;
      EXPECT_GT(times.span_s, 0.0) << episode;
      for (double seconds : times.parts) EXPECT_GE(seconds, 0.0) << episode;
      EXPECT_LE(MeasuredParts(times), times.span_s + 1e-9) << episode;
      EXPECT_GT(times.part(EpisodeTimes::kPhysics), 0.0) << episode;
      EXPECT_GT(times.part(EpisodeTimes::kRender), 0.0) << episode << ": the head camera is rendered";
      EXPECT_GT(times.part(EpisodeTimes::kPolicy), 0.0) << episode << ": the expert acts";
      EXPECT_EQ(times.part(EpisodeTimes::kVideo), 0.0) << episode << ": nothing films it";
      // A slot's worker does nothing else while its episode runs: every moment is one of its parts.
      if (!lock_step) {
        EXPECT_NEAR(MeasuredParts(times), times.span_s, 1e-9) << episode;
      }
      all_parts += MeasuredParts(times);
    }
    // Lock-step, each moment is shared among the episodes live then: together no more than the cell's time.
    if (lock_step) {
      EXPECT_LE(all_parts, result.wall_s) << label;
    }
  }
}

}  // namespace
}  // namespace tavis::batch::cell

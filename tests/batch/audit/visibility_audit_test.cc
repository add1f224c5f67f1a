// The visibility audit: what the cameras see at reset and at the expert's fixation, a black
// camera seeing nothing, and results independent of the thread and slot counts.
#include "batch/audit/visibility_audit.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace tavis::batch::audit {
namespace {

AuditConfig SmallAudit(const std::string& task, int episodes) {
  AuditConfig config;
  config.scene.task = task;
  config.scene.robot = "gr1t2";
  config.episodes = episodes;
  config.image_width = 112;
  config.image_height = 112;
  config.scene.config_dir = TAVIS_CONFIG_DIR;
  return config;
}

int CameraIndex(const AuditResult& result, const std::string& name) {
  for (std::size_t c = 0; c < result.cameras.size(); ++c) {
    if (result.cameras[c] == name) return static_cast<int>(c);
  }
  ADD_FAILURE() << "no camera " << name;
  return 0;
}

// conditional-pick's information is the card: the expert reads it with the head before it looks
// at the target, and at that fixation the card fills a good part of its own pixels in the head
// image. GR1T2's level head sees neither the card nor the target at reset.
TEST(VisibilityAudit, HeadSeesTheCueCardAtItsFixation) {
  const AuditResult result = RunVisibilityAudit(SmallAudit("conditional-pick", 4));
  ASSERT_EQ(result.objects, (std::vector<std::string>{"target", "cue_card"}));
  ASSERT_EQ(result.cameras, (std::vector<std::string>{"head", "fixed", "left_wrist", "right_wrist"}));
  const int head = CameraIndex(result, "head");
  constexpr int kCard = 1;
  EXPECT_GT(result.Fixated(kCard), 0) << "the expert never fixated the card";
  EXPECT_EQ(result.VisibleAtFixation(kCard, head), result.Fixated(kCard));
  EXPECT_EQ(result.VisibleAtReset(kCard, head), 0);
  for (const EpisodeAudit& episode : result.episodes) {
    SCOPED_TRACE("episode " + std::to_string(episode.episode));
    const ObjectAudit& card = episode.objects[kCard];
    if (!card.at_fixation) continue;
    EXPECT_GT((*card.at_fixation)[head], 0.5);
    EXPECT_GT(card.fixation_tick, 0);
    const ObjectAudit& target = episode.objects[0];
    if (target.at_fixation) {
      EXPECT_GT(target.fixation_tick, card.fixation_tick) << "the card is read first";
    }
    for (double fraction : card.at_reset) {
      EXPECT_GE(fraction, 0.0);
      EXPECT_LE(fraction, 1.0);
    }
  }
}

// blocked-clutter-pick-cube's head is black: it counts nothing visible, at reset or at the
// fixation, while the fixed camera sees the cube the expert fixates.
TEST(VisibilityAudit, BlackHeadSeesNothing) {
  const AuditResult result = RunVisibilityAudit(SmallAudit("blocked-clutter-pick-cube", 3));
  const int head = CameraIndex(result, "head");
  ASSERT_GT(result.Fixated(0), 0);
  EXPECT_EQ(result.VisibleAtReset(0, head), 0);
  EXPECT_EQ(result.VisibleAtFixation(0, head), 0);
  for (const EpisodeAudit& episode : result.episodes) {
    EXPECT_EQ(episode.objects[0].at_reset[static_cast<std::size_t>(head)], 0.0);
    if (episode.objects[0].at_fixation) {
      EXPECT_EQ((*episode.objects[0].at_fixation)[static_cast<std::size_t>(head)], 0.0);
    }
  }
  EXPECT_GT(result.VisibleAtFixation(0, CameraIndex(result, "fixed")), 0);
}

// Without the head image, blocked-clutter-pick-cube's expert finds the cube with a wrist camera:
// at its fixation the wrist on the cube's side looks at the cube, on either robot.
TEST(VisibilityAudit, BlockedClutterExpertSeesTheCubeWithAWristCamera) {
  for (const char* robot : {"gr1t2", "reachy2"}) {
    SCOPED_TRACE(robot);
    AuditConfig config = SmallAudit("blocked-clutter-pick-cube", 8);
    config.scene.robot = robot;
    const AuditResult result = RunVisibilityAudit(config);
    const int left = CameraIndex(result, "left_wrist");
    const int right = CameraIndex(result, "right_wrist");
    ASSERT_EQ(result.Fixated(0), 8);
    const int at_reset = result.VisibleAtReset(0, left) + result.VisibleAtReset(0, right);
    EXPECT_GE(result.VisibleAtFixation(0, left) + result.VisibleAtFixation(0, right), std::max(7, at_reset + 4))
        << "the wrists at rest mostly look away; the look brings the cube into view";
  }
}

// Every episode's visible fractions at reset, object by object and camera by camera.
std::vector<CameraFractions> FractionsAtReset(const AuditResult& result) {
  std::vector<CameraFractions> fractions;
  for (const EpisodeAudit& episode : result.episodes) {
    for (const ObjectAudit& object : episode.objects) fractions.push_back(object.at_reset);
  }
  return fractions;
}

// The audit runs its scene under the perturbation levels it is given, as every front end does
// (scene::PlanScene): the fixed camera moved sees the cluttered target otherwise, and an
// unknown level is refused naming it.
TEST(VisibilityAudit, RunsUnderThePerturbationLevelsGiven) {
  const AuditConfig base = SmallAudit("clutter-pick-cube", 2);
  AuditConfig moved = base;
  moved.scene.perturbations = {"camera:fixed-view-large"};
  EXPECT_NE(FractionsAtReset(RunVisibilityAudit(moved)), FractionsAtReset(RunVisibilityAudit(base)));
  AuditConfig unknown = base;
  unknown.scene.perturbations = {"camera:no-such-level"};
  try {
    RunVisibilityAudit(unknown);
    ADD_FAILURE() << "an unknown level was accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("no level 'no-such-level'"), std::string::npos) << error.what();
  }
}

AuditResult RunWith(AuditConfig config, std::size_t threads, int envs) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  config.envs = envs;
  return RunVisibilityAudit(config);
}

// Every episode's fractions and fixation ticks, exactly, with 1 thread and 2 slots and with 2
// threads and 3 slots (episodes refilled into slots in a different order).
TEST(VisibilityAudit, SameResultsForAnyThreadAndSlotCount) {
  const AuditConfig config = SmallAudit("wait-then-act", 5);
  const AuditResult a = RunWith(config, 1, 2);
  const AuditResult b = RunWith(config, 2, 3);
  ASSERT_EQ(a.episodes.size(), b.episodes.size());
  ASSERT_EQ(a.objects, (std::vector<std::string>{"target", "signal_light"}));
  for (std::size_t i = 0; i < a.episodes.size(); ++i) {
    SCOPED_TRACE("episode " + std::to_string(i));
    EXPECT_EQ(a.episodes[i].episode, static_cast<int64_t>(i));
    for (std::size_t o = 0; o < a.objects.size(); ++o) {
      const ObjectAudit& x = a.episodes[i].objects[o];
      const ObjectAudit& y = b.episodes[i].objects[o];
      EXPECT_EQ(x.at_reset, y.at_reset) << a.objects[o];
      EXPECT_EQ(x.at_fixation, y.at_fixation) << a.objects[o];
      EXPECT_EQ(x.fixation_tick, y.fixation_tick) << a.objects[o];
    }
  }
}

}  // namespace
}  // namespace tavis::batch::audit

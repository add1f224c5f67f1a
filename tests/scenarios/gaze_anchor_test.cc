#include "scenarios/gaze_anchor.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scenarios/registry.h"
#include "scenarios/scenario.h"

namespace tavis::scenarios {
namespace {

std::vector<std::string> Names(const ScenarioDef& scenario) {
  std::vector<std::string> names;
  for (const GazeAnchor& anchor : scenario.gaze_anchors) names.push_back(anchor.name);
  return names;
}

// Each task declares the anchors of its own structure: a cue before the reach where it has one,
// the target before the grasp and before its success rule's raise.
TEST(GazeAnchor, EveryTaskDeclaresTheAnchorsItHas) {
  using Names_ = std::vector<std::string>;
  EXPECT_EQ(Names(FindScenario("conditional-pick")), (Names_{"card_to_reach", "target_to_grasp", "target_to_lift"}));
  EXPECT_EQ(Names(FindScenario("wait-then-act")), (Names_{"light_to_reach", "target_to_grasp", "target_to_lift"}));
  EXPECT_EQ(Names(FindScenario("multi-shelf-scan")), (Names_{"target_to_grasp", "target_to_pull"}));
  for (const char* task :
       {"clutter-pick-lift", "clutter-pick-cube", "blocked-clutter-pick-cube", "occluded-reach", "peeking-box"}) {
    EXPECT_EQ(Names(FindScenario(task)), (Names_{"target_to_grasp", "target_to_lift"})) << task;
  }
  const GazeAnchor& card = FindScenario("conditional-pick").gaze_anchors[0];
  EXPECT_EQ(card.fixation, GazeAnchor::Fixation::kCue);
  EXPECT_EQ(card.event, GazeAnchor::Event::kReachOnset);
}

// A stage event names one of the task's own stages, and a cue anchor only a task with a cue.
TEST(GazeAnchor, AnchorsNameTheTasksStagesAndCues) {
  for (const ScenarioDef& scenario : AllScenarios()) {
    SCOPED_TRACE(scenario.name);
    EXPECT_FALSE(scenario.gaze_anchors.empty());
    for (const GazeAnchor& anchor : scenario.gaze_anchors) {
      if (anchor.fixation == GazeAnchor::Fixation::kCue) {
        EXPECT_FALSE(scenario.cue_objects.empty()) << anchor.name;
      }
      if (anchor.event != GazeAnchor::Event::kStage) continue;
      bool found = false;
      for (const StageDef& stage : scenario.stages) found |= stage.name == anchor.stage;
      EXPECT_TRUE(found) << anchor.name << " names " << anchor.stage;
    }
  }
}

TEST(GazeAnchor, APickWithoutARaiseStageIsRefused) {
  EXPECT_THROW(PickGazeAnchors({}), std::invalid_argument);
  EXPECT_STREQ(ToString(GazeAnchor::Event::kReachOnset), "reach_onset");
  EXPECT_STREQ(ToString(GazeAnchor::Fixation::kCue), "cue");
}

}  // namespace
}  // namespace tavis::scenarios

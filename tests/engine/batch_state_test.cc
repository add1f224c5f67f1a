#include "engine/batch_state.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace tavis::engine {
namespace {

TEST(BatchState, RowsAreFieldMajorSlicesOfOneArrayPerField) {
  BatchState state;
  state.Allocate(3, 5, 4);
  EXPECT_EQ(state.q_row(2) - state.q.data(), 2 * 5);
  EXPECT_EQ(state.gripper_gap_row(1) - state.gripper_gap.data(), 1 * kGrippersPerEnv);
  EXPECT_EQ(state.gripper_command_row(2) - state.gripper_command.data(), 2 * kGrippersPerEnv);
  EXPECT_EQ(state.object_pose_row(1, 3) - state.object_pose.data(), (1 * 4 + 3) * kObjectPoseSize);
  EXPECT_EQ(state.object_velocity_row(2, 1) - state.object_velocity.data(), (2 * 4 + 1) * kObjectVelocitySize);
  EXPECT_EQ(state.object_rgb_row(1, 2) - state.object_rgb.data(), (1 * 4 + 2) * 3);
  EXPECT_EQ(&state.object_enabled_at(2, 3) - state.object_enabled.data(), 2 * 4 + 3);
}

TEST(BatchState, TaskVariablesAreTypedAndStartUnset) {
  BatchState state;
  state.Allocate(2, 1, 6);
  EXPECT_EQ(state.task[1].target, -1);
  EXPECT_EQ(state.task[1].target_move_tick, -1);
  state.task[1].target = 5;
  EXPECT_EQ(state.target(1), 5);
  EXPECT_FALSE(state.running(0)) << "a slot holds no episode until reset";
  state.episode[0] = 3;
  EXPECT_TRUE(state.running(0));
  state.end[0] = EpisodeEnd::kStopped;
  EXPECT_FALSE(state.running(0));
  EXPECT_STREQ(ToString(EpisodeEnd::kStopped), "stopped");
}

// Records name their ends (episodes.jsonl) and resumed cells read them back: every end has its
// own name and parses to itself.
TEST(BatchState, EveryEpisodeEndsNameParsesBackToIt) {
  std::set<std::string> names;
  for (int i = 0; i <= static_cast<int>(EpisodeEnd::kGaveUp); ++i) {
    const EpisodeEnd end = static_cast<EpisodeEnd>(i);
    const std::string name = ToString(end);
    EXPECT_NE(name, "unknown");
    EXPECT_TRUE(names.insert(name).second) << name << " names two ends";
    EpisodeEnd parsed = EpisodeEnd::kRunning;
    EXPECT_TRUE(ParseEpisodeEnd(name, &parsed)) << name;
    EXPECT_EQ(parsed, end) << name;
  }
  EXPECT_EQ(std::string(ToString(EpisodeEnd::kGaveUp)), "gave_up");
  EpisodeEnd parsed = EpisodeEnd::kRunning;
  EXPECT_FALSE(ParseEpisodeEnd("gave up", &parsed));
}

// The invariant tier aborts with a message naming the broken contract (internal bugs are not
// exceptions: user input is checked where it is read).
TEST(BatchStateDeathTest, OutOfRangeIndicesAbortNamingTheContract) {
  BatchState state;
  state.Allocate(2, 3, 4);
  EXPECT_DEATH(state.q_row(2), "invariant violated.*env index in range");
  EXPECT_DEATH(state.object_pose_row(0, 4), "invariant violated.*object index in range");
  EXPECT_DEATH(state.target(0), "invariant violated.*target object");
}

}  // namespace
}  // namespace tavis::engine

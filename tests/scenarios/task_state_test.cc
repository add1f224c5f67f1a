// A task's own per-env variables (scenarios/task_state.h) in the engine's per-env blocks: a reset
// starts them at their defaults whatever the block held, each env's are its own, and the blocks
// are one array of cache lines allocated with the batch.
#include "scenarios/task_state.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>

namespace tavis::scenarios {
namespace {

struct ExampleVars {
  int count = 7;
  double level = 0.5;
  bool flag = false;
};

TEST(TaskState, AResetStartsTheVariablesAtTheirDefaultsAndEachEnvHasItsOwn) {
  engine::BatchState state;
  state.Allocate(3, 1, 1);
  ASSERT_EQ(state.task_state.size(), 3u);
  for (int env = 0; env < 3; ++env) {
    for (std::size_t byte = 0; byte < engine::kTaskStateBytes; ++byte)
      EXPECT_EQ(state.task_state_row(env)[byte], 0) << "a fresh batch's blocks are zero";
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(state.task_state_row(env)) % 64, 0u) << "a cache line each";
  }
  EXPECT_EQ(state.task_state_row(1) - state.task_state_row(0), static_cast<std::ptrdiff_t>(engine::kTaskStateBytes))
      << "one array, env after env";

  std::memset(state.task_state_row(1), 0xAB, engine::kTaskStateBytes);  // what a previous episode left
  ExampleVars& vars = ResetTaskState<ExampleVars>(state, 1);
  EXPECT_EQ(vars.count, 7);
  EXPECT_EQ(vars.level, 0.5);
  EXPECT_FALSE(vars.flag);
  vars.count = 9;
  ResetTaskState<ExampleVars>(state, 2).flag = true;
  EXPECT_EQ(TaskState<ExampleVars>(state, 1).count, 9);
  EXPECT_FALSE(TaskState<ExampleVars>(state, 1).flag);
  const engine::BatchState& read_only = state;
  EXPECT_TRUE(TaskState<ExampleVars>(read_only, 2).flag);
  EXPECT_EQ(TaskState<ExampleVars>(read_only, 2).count, 7);
  EXPECT_EQ(state.task_state_row(0)[0], 0) << "another env's block is untouched";
}

}  // namespace
}  // namespace tavis::scenarios

// A task's own per-env variables, declared by the task as a plain struct (wait-then-act's light,
// conditional-pick's card, peeking-box's open side) and kept in the engine's per-env block
// (engine::TaskStateBlock), which the rest of the program never reads. The task's reset hook
// starts them (ResetTaskState); its other hooks and its expert's callbacks read them (TaskState).
#pragma once

#include <new>
#include <type_traits>

#include "engine/batch_state.h"

namespace tavis::scenarios {

// A task's variables are plain values that fit the block: copied with the BatchState byte for
// byte, never destroyed, and so never a heap allocation.
template <typename Vars>
constexpr void CheckTaskStateType() {
  static_assert(std::is_trivially_copyable_v<Vars> && std::is_trivially_destructible_v<Vars>,
                "a task's variables are plain values");
  static_assert(sizeof(Vars) <= engine::kTaskStateBytes, "a task's variables fit engine::kTaskStateBytes");
  static_assert(alignof(Vars) <= alignof(engine::TaskStateBlock), "a task's variables fit the block's alignment");
}

// Starts the task's variables of env's new episode at their defaults; the reset hook calls it
// once, before it sets them.
template <typename Vars>
Vars& ResetTaskState(engine::BatchState& state, int env) {
  CheckTaskStateType<Vars>();
  return *::new (static_cast<void*>(state.task_state_row(env))) Vars{};
}

// The task's variables of env's episode (after its reset).
template <typename Vars>
Vars& TaskState(engine::BatchState& state, int env) {
  CheckTaskStateType<Vars>();
  return *std::launder(reinterpret_cast<Vars*>(state.task_state_row(env)));
}
template <typename Vars>
const Vars& TaskState(const engine::BatchState& state, int env) {
  CheckTaskStateType<Vars>();
  return *std::launder(reinterpret_cast<const Vars*>(state.task_state_row(env)));
}

}  // namespace tavis::scenarios

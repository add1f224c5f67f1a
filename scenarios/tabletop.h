// Facts the table-top tasks share (reference 4.1-4.4, 4.6-4.8): where objects are dropped onto
// the table, how high a lifted target must be, and the prompts of tasks that name their target.
#pragma once

#include <array>

#include "engine/batch_state.h"

namespace tavis::scenarios {

inline constexpr double kObjectDropZ = 1.1;             // m: objects start here and settle on the table top (1.0 m)
inline constexpr double kHeadLiftSuccessZ = 1.2;        // m: TAVIS-Head lifts succeed above this
inline constexpr double kHandsLiftSuccessZ = 1.25;      // m: TAVIS-Hands lifts (peeking-box, occluded-reach)
inline constexpr double kExpertLiftPastSuccess = 0.07;  // m: the expert lifts this far past the success height

// Tasks that name their target in the prompt (clutter-pick-lift, multi-shelf-scan): three
// phrasings per YCB object, in TAVIS_HEAD_OBJECT_NAMES order.
using TargetPrompts = std::array<std::array<const char*, 3>, 5>;

// The env's prompt: its target's phrasing TaskVars::prompt_variant.
const char* TargetPrompt(const TargetPrompts& prompts, const engine::BatchState& state, int env);

}  // namespace tavis::scenarios

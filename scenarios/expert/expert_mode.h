// How the scripted expert uses its head. The reference's teleoperators look first, so its expert
// does (gaze-first). Head-still is ours, for the fixed-camera bias ablation (docs/fidelity.md):
// the neck never moves and the hands start as soon as the task lets them.
#pragma once

#include <string>

namespace tavis::scenarios::expert {

enum class ExpertMode {
  // Reads the cue and fixates the target, lets the head settle, then acts (the default).
  kGazeFirst,
  // The neck command stays at its reset pose in every tick and nothing waits for gaze; the hands
  // wait only for what the task requires (the dropped objects at rest, a go signal).
  kHeadStill,
};

// Accepts "gaze-first" and "head-still"; throws std::invalid_argument naming the value and the
// accepted ones.
ExpertMode ParseExpertMode(const std::string& text);
const char* ToString(ExpertMode mode);
// "gaze-first, head-still", for --help texts.
const char* ExpertModeNames();

}  // namespace tavis::scenarios::expert

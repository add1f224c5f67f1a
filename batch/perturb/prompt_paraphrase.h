// The language perturbation axis at run time (docs/perturbations.md): which instruction an
// episode is served and recorded with.
#pragma once

#include <string>

#include "engine/batch_state.h"
#include "engine/world_model.h"
#include "scenarios/scenario.h"

namespace tavis::batch::perturb {

// The instruction of env's episode, right after its reset. Under a language level: one of the
// level's paraphrases for the task, drawn from the episode's own stream (seed,
// RandomStreamId::kParaphrase, episode), with "{object}" replaced by the level's name for the
// target. Otherwise the task's own prompt ("" for a task without one).
std::string EpisodePrompt(const engine::WorldModel& model, const scenarios::ScenarioDef& scenario,
                          const engine::BatchState& state, int env);

}  // namespace tavis::batch::perturb

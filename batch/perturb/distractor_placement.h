// The distractors perturbation axis at run time (docs/perturbations.md): the extra objects in the
// world, and where each episode stands them.
#pragma once

#include "engine/batch_state.h"
#include "engine/world_model.h"
#include "scenarios/scenario.h"

namespace tavis::batch::perturb {

// m: the least gap between a distractor's footprint and any other object's, so that none stands
// on, against or between the task's objects.
inline constexpr double kDistractorClearance = 0.03;

// Appends one object per distractor kind of the model's EpisodePerturbation after the task's own:
// dynamic (the hand may touch them), named "distractor_<kind>", drawn in the palette's
// "distractor" appearance with its kind's colour. Nothing without a distractors level.
void AddDistractorObjects(engine::WorldModel* model);

// The distractors of env's episode, right after its task's reset (which they do not change):
// `count` kinds drawn from the episode's own stream (seed, RandomStreamId::kDistractors,
// episode), each stood upright at rest, square to its zone's edges give or take 15 degrees (a
// quarter turn drawn too), at a random place of the task's distractor zones where its whole
// footprint lies in the zone, kDistractorClearance from every object of the task and every
// distractor placed before it that stands on or will land on its surface, and clear of the static
// parts. The kinds not drawn, and one that finds no such place in a thousand tries, are left out
// (disabled). Nothing without a distractors level.
void PlaceDistractors(const engine::WorldModel& model, const scenarios::ScenarioDef& scenario,
                      engine::BatchState& state, int env);

}  // namespace tavis::batch::perturb

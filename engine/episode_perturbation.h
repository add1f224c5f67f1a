// What a cell's scene perturbation levels (docs/perturbations.md: distractors, language, runtime)
// change in its episodes, carried in the WorldModel beside the view perturbations so that every
// VecEnv made from the model (eval, demos, render) runs the same episodes. Unlike the view axes
// these reach the physics (distractors stand on the table, the runtime axis moves the target) or
// the prompt (language); the task's own random draws are untouched, so episode i keeps its base
// scene. The defaults change nothing.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "kinematics/pose.h"
#include "kinematics/shape.h"

namespace tavis::engine {

// An object no task places (a mug, a ball, a book): its shape, mass and colour.
struct DistractorKind {
  std::string name;  // as the level file names it ("mug"); the world's object is "distractor_<name>"
  Shape shape;
  double mass_kg = 0.0;
  Vec3 rgb = Vec3::Constant(0.5);  // linear reflectance
};

// distractors axis. The world holds one object per kind, after the task's own objects; each
// episode stands `count` of them, drawn from its own stream, on the task's distractor zones
// (scenarios::ScenarioDef::distractor_zones) and leaves the others out.
struct DistractorSettings {
  int count = 0;
  std::vector<DistractorKind> kinds;
};

// runtime axis. The first control tick a hand's tool centre point comes within trigger_m of the
// target's centre, the target is moved distance_m horizontally, once per episode.
struct TargetMoveSettings {
  double trigger_m = 0.0;
  double distance_m = 0.0;
};

// language axis. Per task name, the paraphrases its episodes' prompts are drawn from; "{object}"
// in a paraphrase stands for object_names[the target's model name].
struct LanguageSettings {
  std::map<std::string, std::vector<std::string>> paraphrases;
  std::map<std::string, std::string> object_names;
};

struct EpisodePerturbation {
  DistractorSettings distractors;
  TargetMoveSettings target_move;
  LanguageSettings language;
  uint64_t seed = 0;  // the cell's seed: each axis's stream is keyed by (seed, episode)

  bool adds_distractors() const { return distractors.count > 0; }
  bool moves_target() const { return target_move.distance_m > 0.0; }
  bool paraphrases_prompt() const { return !language.paraphrases.empty(); }
  // The objects the distractors axis added to the world.
  int num_distractor_objects() const { return static_cast<int>(distractors.kinds.size()); }
};

}  // namespace tavis::engine

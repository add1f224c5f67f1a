// The perturbation axes (docs/perturbations.md): each axis is a YAML file of its own,
// <config_dir>/perturbations/<axis>.yaml, declaring named severity levels. A cell chooses at most
// one level per axis ("camera:head-shift", `tavis eval --perturb`); its chosen levels are applied
// to the world model before any env is built: the view axes (camera, sensor, lighting) to its
// RenderPerturbation, the episode axes (distractors, language, runtime) to its
// EpisodePerturbation (episode_perturbation_levels.h). Read strictly: an unknown key,
// a level that changes nothing, a value out of range or a file whose axis: is not its name is a
// configs::ConfigError naming the file, the key and the value.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/episode_perturbation.h"
#include "engine/render_perturbation.h"
#include "engine/world_model.h"

namespace tavis::batch::perturb {

// The axes this program implements, in the order docs/perturbations.md lists them.
const std::vector<std::string>& PerturbationAxisNames();

struct PerturbationChoice {
  std::string axis;
  std::string level;
  std::string text() const { return axis + ":" + level; }
};

// "AXIS:LEVEL"; throws std::invalid_argument naming the text when it is not of that form or the
// axis is not one of PerturbationAxisNames().
PerturbationChoice ParsePerturbationChoice(const std::string& text);

// The label suffix a sweep gives a perturbed cell: ".camera.fov-wide.sensor.noise-low" for
// {"camera:fov-wide", "sensor:noise-low"}; "" for none.
std::string PerturbationLabelSuffix(const std::vector<std::string>& choices);

struct PerturbationLevel {
  std::string axis;
  std::string name;
  std::string description;
  engine::RenderPerturbation effect;           // only this axis's fields differ from the defaults
  engine::EpisodePerturbation episode_effect;  // the same for the episode axes
  nlohmann::ordered_json settings;             // the level's keys and values as the file gives them
};

// Every level of one axis, in file order. Throws configs::ConfigError (file, key, value).
std::vector<PerturbationLevel> LoadPerturbationAxis(const std::string& config_dir, const std::string& axis);

// The levels `choices` ("AXIS:LEVEL" each) name, checked: an unknown axis or level (the error
// lists the known ones) or an axis chosen twice throws std::invalid_argument.
std::vector<PerturbationLevel> ResolvePerturbations(const std::string& config_dir,
                                                    const std::vector<std::string>& choices);

// The chosen levels' effects combined, the sensor noise and random texture colours keyed by `seed`.
engine::RenderPerturbation CombinePerturbations(const std::vector<PerturbationLevel>& levels, uint64_t seed);
// The same for the episode axes, their streams keyed by `seed`.
engine::EpisodePerturbation CombineEpisodePerturbations(const std::vector<PerturbationLevel>& levels, uint64_t seed);

// What a cell records (cell.json, summary.json) and a resume compares: per choice its axis,
// level and the level's settings as read, so an edited level file is a different setting.
nlohmann::json PerturbationsJson(const std::vector<PerturbationLevel>& levels);

// Applies `choices` to `model` (ResolvePerturbations, CombinePerturbations,
// CombineEpisodePerturbations) and adds the distractor objects a distractors level needs after the
// task's own (distractor_placement.h); none: unchanged.
void ApplyPerturbations(const std::string& config_dir, const std::vector<std::string>& choices, uint64_t seed,
                        engine::WorldModel* model);
// The same for levels already resolved (a cell's plan resolves them once); none: unchanged.
void ApplyPerturbationLevels(const std::vector<PerturbationLevel>& levels, uint64_t seed, engine::WorldModel* model);

}  // namespace tavis::batch::perturb

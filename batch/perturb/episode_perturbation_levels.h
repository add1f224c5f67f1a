// The level keys of the perturbation axes that change episodes rather than views
// (docs/perturbations.md): distractors (extra objects on the table), language (prompt
// paraphrases) and runtime (the target moved under the approaching hand). The catalog
// (perturbation_catalog.h) reads each such file's common keys (axis, levels, name, description)
// and hands every level to its axis's reader here, which reads the level's own keys, strictly,
// into engine::EpisodePerturbation and the settings a cell records.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "configs/yaml_reader.h"
#include "engine/episode_perturbation.h"

namespace tavis::batch::perturb {

// Reads one level of the axis: `file` is the whole file (its file-level keys, such as the
// distractor objects every level draws from), `level` the level's mapping. Writes the level's
// effect and its keys and values as read (a resume compares them). Throws configs::ConfigError
// naming the file, key and value.
using EpisodeLevelReader = void (*)(const configs::YamlValue& file, const configs::YamlValue& level,
                                    engine::EpisodePerturbation* effect, nlohmann::ordered_json* settings);

// The reader of `axis`, or null when the axis changes only views.
EpisodeLevelReader FindEpisodeLevelReader(const std::string& axis);

}  // namespace tavis::batch::perturb

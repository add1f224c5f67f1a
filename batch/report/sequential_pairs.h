// Which cells of a sweep a sequential paired test compares (sequential_test.h), and the groups
// that stop together. Episode i of two cells of the same task, robot, split and seed has the same
// scene, so the cells pair episode by episode: head against every other camera protocol of the
// same label (fixed and the camera sets), the base scene against each perturbation (same camera),
// and label A against label B for the label pairs the spec names (same camera and perturbation).
// A cell in several pairs (head against fixed and against head-only) ties them into one group:
// the sweep runs a group's cells in blocks and stops them all at the same episode count, the first
// look at which every pair of the group has decided, or at the cap.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/cell/cell_settings.h"
#include "batch/report/sequential_test.h"

namespace tavis::batch::report {

struct SequentialSettings {
  bool enabled = false;
  SequentialTestSettings test;
  bool cameras = true;                                        // head vs each other camera protocol
  bool perturbations = true;                                  // base scene vs each perturbation
  std::vector<std::pair<std::string, std::string>> policies;  // label pairs (first, second)
};

// The spec's `sequential:` as JSON ({alpha, block, pairs, policies}), and back (a summary's
// spec); a JSON without it (null) is off.
nlohmann::ordered_json SequentialSettingsJson(const SequentialSettings& settings);
SequentialSettings SequentialSettingsFromJson(const nlohmann::ordered_json& json);

// A cell as pairing sees it: its settings and its label (a perturbed cell's ends in the suffix).
struct PairingCell {
  const cell::EvaluationCellConfig* config;
  std::string label;
};

struct SequentialPair {
  std::string kind;   // "camera" (first: head), "perturbation" (first: base scene), "policy"
  std::size_t first;  // positions in the cells given
  std::size_t second;
};

// Every pair the settings test, in cell order of the first then the second.
std::vector<SequentialPair> SequentialPairs(const std::vector<PairingCell>& cells, const SequentialSettings& settings);

// The groups of cells joined by pairs (positions, ascending; groups in the order of their first
// cell); a cell in no pair is in none.
std::vector<std::vector<std::size_t>> SequentialGroups(std::size_t cell_count,
                                                       const std::vector<SequentialPair>& pairs);

// Success per episode of the first `count` records of a cell, for the test.
using Outcomes = std::vector<bool>;

// Whether every pair among `pairs` (each the outcomes of its two cells, cut to the same length)
// has decided by its last look.
bool EveryPairDecided(const std::vector<std::pair<const Outcomes*, const Outcomes*>>& pairs,
                      const SequentialTestSettings& settings);

}  // namespace tavis::batch::report

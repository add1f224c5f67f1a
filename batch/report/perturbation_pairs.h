// Perturbed cells paired with their base cells (docs/perturbations.md): per policy label, the
// perturbation, task, robot, split and camera protocol, episode i under the perturbation against
// episode i in the base scene (same seed, so the same scene), over every seed both cells ran:
// counts of both / base only / perturbed only / neither and McNemar's exact p. summary.json's
// "paired_perturbations" (present when the sweep has a perturbed cell) and its table.
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "batch/report/sweep_summary.h"
#include "batch/report/sweep_tables.h"

namespace tavis::batch::report {

// Rows {label, perturbation, task, robot, split, camera, pairs, both, base_only, perturbed_only,
// neither, base_rate, perturbed_rate, difference, mcnemar_p}; the label is the base cell's.
nlohmann::ordered_json PerturbationPairRows(const std::vector<CellEpisodes>& cells);

TextTable PerturbationPairTable(const nlohmann::ordered_json& summary);

}  // namespace tavis::batch::report

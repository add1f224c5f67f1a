// Checkpoints that are training seeds of one recipe (a spec's seed_group): every success rate and
// suite mean of the group's labels as the mean and spread across the checkpoints. Each
// checkpoint's rate pools its own evaluation seeds first; checkpoints are never pooled.
#pragma once

#include <nlohmann/json.hpp>

namespace tavis::batch::report {

// summary["seed_groups"]: per group {seed_group, labels, rows: per (suite, task, robot, split,
// camera) {labels (the checkpoints that evaluated it, e.g. only a robot's own), values (one per
// label, in label order), n, mean, std (sample, n - 1; 0 for one checkpoint), min, max},
// suite_means: the same per (suite, robot, split, camera) over the labels' task averages}.
// Reads summary["labels"] and summary["success"].
nlohmann::ordered_json SeedGroupsJson(const nlohmann::ordered_json& summary);

// {values, n, mean, std, min, max} of `values` (std: sample standard deviation, 0 when n = 1).
nlohmann::ordered_json AcrossCheckpoints(const std::vector<double>& values);

}  // namespace tavis::batch::report

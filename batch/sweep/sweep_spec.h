// A sweep spec (configs/sweeps/*.yaml): the evaluation cells of a sweep as the product of tasks
// (named or by suite), robots, splits, camera protocols and seeds, each cell N episodes of one
// policy. Read strictly: an unknown key, a missing key or a bad value is an error naming the file,
// the key and the value.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/cell/evaluation_cell.h"
#include "batch/report/sequential_pairs.h"
#include "batch/sweep/policy_spec.h"

namespace tavis::batch::sweep {

struct SweepSpec {
  std::string source;               // the file it was read from, for messages
  std::vector<std::string> suites;  // as given
  std::vector<std::string> tasks;   // the suites' tasks in suite order, then the named ones, no repeats
  std::vector<std::string> robots;
  std::vector<scenarios::Split> splits;
  std::vector<CameraProtocol> cameras;
  std::vector<uint64_t> seeds;
  int episodes = 96;
  int envs = 32;   // env slots per cell (results do not depend on it)
  int videos = 0;  // film each cell's first N episodes into cells/<id>/videos (episode_videos.h); 0: none
  // The labelled policies (a spec's single `policy:` is one, labelled by its name), each serving
  // the cells its filter allows; two labels may serve the same cell (they are separate cells).
  std::vector<PolicySpec> policies;
  // The perturbation dimension (perturbations:): each entry a set of "AXIS:LEVEL" choices, the
  // empty set being the base scene ("none" in the file). Default: only the base scene. A perturbed
  // cell's label is its policy's label followed by ".AXIS.LEVEL" per choice, so tables and reports
  // show it beside its base cell, with which it pairs episode by episode.
  std::vector<std::vector<std::string>> perturbations = {{}};
  // Which labels the paper's figures and headline numbers take (figures:); empty: the defaults
  // of report::FigureChoices.
  nlohmann::ordered_json figures = nlohmann::ordered_json::object();
  // sequential: the opt-in sequential paired test (sequential_spec.h); off by default.
  report::SequentialSettings sequential;
};

struct SweepCell {
  std::string id;  // <task>_<robot>_<split>_<camera>_<label>_s<seed>, its folder under cells/
  cell::EvaluationCellConfig config;
  std::string label;
  std::string seed_group;
};

// Throws configs::ConfigError ("FILE: key: message, got VALUE") for any mistake; robots must be
// among configs_dir's robots/*.yaml; the files the policies name are read unless `files` says not
// (ReadPolicySpec).
SweepSpec LoadSweepSpec(const std::string& path, const std::string& config_dir, PolicyFiles files = PolicyFiles::kRead);
SweepSpec ParseSweepSpec(const std::string& yaml_text, const std::string& source_name, const std::string& config_dir,
                         PolicyFiles files = PolicyFiles::kRead);

// The spec's settings as JSON (what the manifest records and merge compares; not the file name).
nlohmann::ordered_json SweepSpecJson(const SweepSpec& spec);

// "camera:fov-wide+sensor:noise-low" -> {"camera:fov-wide", "sensor:noise-low"}; "none" -> {}.
std::vector<std::string> SplitPerturbationSet(const std::string& text);

// Every cell, ordered task, robot, split, camera, policy, perturbation, seed (the spec's orders); a policy
// only where its cells: filter allows.
std::vector<SweepCell> ExpandCells(const SweepSpec& spec, const std::string& config_dir);

struct Shard {
  int index = 0;  // 0 <= index < count
  int count = 1;
};

// "I/N" with 0 <= I < N; throws output::SettingError (key "shard") naming the text.
Shard ParseShard(const std::string& text);
// Throws output::SettingError (key "shard") unless each of the N shards gets a cell: N <= `cells`.
void RequireShardHoldsCells(const Shard& shard, std::size_t cells);
// Shard I of N holds the cells whose position in ExpandCells() is I mod N.
bool InShard(std::size_t cell_position, const Shard& shard);

}  // namespace tavis::batch::sweep

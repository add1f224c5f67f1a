// One labelled policy of a sweep spec: the policy and its serving options, the cells it serves
// (a filter over the spec's suites, tasks, robots, splits and cameras) and, optionally, the seed
// group it belongs to (checkpoints that are training seeds of one recipe). The policy's options
// are the cell settings that have a key in a spec (cell::CellSettings(), spec_key): they are read,
// checked, forwarded to the cell and written in the manifest from that table, so a new serving
// option is declared there alone.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/cell/evaluation_cell.h"
#include "configs/yaml_reader.h"

namespace tavis::batch::sweep {

struct PolicySpec {
  std::string label;       // names the policy in cell ids, tables and figures; never pooled with another
  std::string seed_group;  // empty: none; else the recipe whose training seeds this checkpoint is one of
  // The policy (settings.policy) and its options; the settings a spec cannot name keep their
  // defaults.
  cell::EvaluationCellConfig settings;
  // The cells it serves: empty lists mean every one of the spec's.
  std::vector<std::string> tasks;  // the filter's suites expanded, then its tasks
  std::vector<std::string> robots;
  std::vector<scenarios::Split> splits;
  std::vector<CameraProtocol> cameras;

  bool Serves(const cell::EvaluationCellConfig& cell) const;
  // Copies the policy and its options (every setting a spec can name) into a cell's settings.
  void ApplyTo(cell::EvaluationCellConfig& cell) const;
};

// Whether reading a spec reads the files its policies name: a sweep about to run does (so that it
// does not stop at its first cell), a merge of finished shards does not need them.
enum class PolicyFiles { kRead, kNotRead };

// `policy:` (one policy, labelled by its name unless it has a label) or one entry of `policies:`.
// Throws configs::ConfigError naming the key and the value. With PolicyFiles::kRead the files it
// names are read now: the actions CSV, the observation keys (a preset of `config_dir` or a YAML
// file) and match_dataset's meta/info.json.
PolicySpec ReadPolicySpec(const configs::YamlValue& policy, bool label_required,
                          const std::vector<std::string>& known_robots, const std::string& config_dir,
                          PolicyFiles files);

nlohmann::ordered_json PolicySpecJson(const PolicySpec& policy);

// A label is a cell-id part and a file-name part: letters, digits, '-', '.'; 1..64 characters.
bool IsValidLabel(const std::string& label);

}  // namespace tavis::batch::sweep

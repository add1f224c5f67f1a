#include "batch/sweep/sweep_spec.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <limits>
#include <map>
#include <stdexcept>

#include "batch/cell/cell_folder_name.h"
#include "batch/output/setting_error.h"
#include "batch/perturb/perturbation_catalog.h"
#include "batch/sweep/sequential_spec.h"
#include "batch/sweep/spec_lists.h"
#include "configs/robot_config.h"
#include "configs/yaml_reader.h"
#include "scenarios/registry.h"

namespace tavis::batch::sweep {
namespace {

using configs::YamlValue;

uint64_t ReadSeed(const YamlValue& value) {
  const std::string text = value.AsString();
  const bool digits = !text.empty() && text.size() <= 20 &&
                      std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isdigit(c) != 0; });
  if (!digits || (text.size() == 20 && text > "18446744073709551615")) {
    value.Fail("must be an integer from 0 to 18446744073709551615, got " + value.Text());
  }
  return std::stoull(text);
}

std::string Join(const std::vector<std::string>& names, const std::string& separator) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : separator) + name;
  return text;
}

const std::string& NameOf(const std::string& name) { return name; }
std::string NameOf(scenarios::Split split) { return scenarios::ToString(split); }
std::string NameOf(CameraProtocol camera) { return ToString(camera); }

// A policy's cells: filter must allow some of the sweep's values of each list it names: one that
// allows none would leave the policy out of the sweep without a word.
template <typename T>
void RequireSomeAllowed(const YamlValue& policy, const char* what, const std::vector<T>& allowed,
                        const std::vector<T>& sweep) {
  if (allowed.empty()) return;
  std::vector<std::string> allowed_names, sweep_names;
  for (const T& value : allowed) {
    if (std::find(sweep.begin(), sweep.end(), value) != sweep.end()) return;
    allowed_names.push_back(NameOf(value));
  }
  for (const T& value : sweep) sweep_names.push_back(NameOf(value));
  policy.Required("cells").Fail(std::string("selects no cell of the sweep: none of its ") + what + " (" +
                                Join(allowed_names, ", ") + ") is among the sweep's (" + Join(sweep_names, ", ") + ")");
}

void RequireFilterSelectsCells(const YamlValue& node, const PolicySpec& policy, const SweepSpec& spec) {
  RequireSomeAllowed(node, "tasks", policy.tasks, spec.tasks);
  RequireSomeAllowed(node, "robots", policy.robots, spec.robots);
  RequireSomeAllowed(node, "splits", policy.splits, spec.splits);
  RequireSomeAllowed(node, "cameras", policy.cameras, spec.cameras);
}

// The spec's policy entries, in the order of SweepSpec::policies.
std::vector<YamlValue> PolicyNodes(const YamlValue& root) {
  if (const auto single = root.Optional("policy")) return {*single};
  return root.Required("policies").Elements();
}

// Every cell label (a policy's label or seed group, followed by its perturbation's suffix) names
// one policy under one perturbation: a policy labelled "expert.runtime.move" beside policy expert
// perturbed by runtime:move would give two cells one id, and the sweep could never finish.
void RequireDistinctCellLabels(const YamlValue& root, const SweepSpec& spec) {
  struct Use {
    std::size_t policy;
    std::size_t perturbation;
    bool group;
  };
  const auto describe = [&spec](const Use& use) {
    const PolicySpec& policy = spec.policies[use.policy];
    std::string text = use.group ? "the seed group '" + policy.seed_group + "' of policy '" + policy.label + "'"
                                 : "policy '" + policy.label + "'";
    const std::vector<std::string>& choices = spec.perturbations[use.perturbation];
    return choices.empty() ? text : text + " under " + Join(choices, "+");
  };
  const std::vector<YamlValue> nodes = PolicyNodes(root);
  std::map<std::string, Use> uses;
  for (std::size_t p = 0; p < spec.policies.size(); ++p) {
    for (std::size_t k = 0; k < spec.perturbations.size(); ++k) {
      for (const bool group : {false, true}) {
        const std::string& base = group ? spec.policies[p].seed_group : spec.policies[p].label;
        if (base.empty()) continue;
        const Use use{p, k, group};
        const std::string name = base + perturb::PerturbationLabelSuffix(spec.perturbations[k]);
        const auto [earlier, first] = uses.emplace(name, use);
        const Use& other = earlier->second;
        // A seed group is shared by its checkpoints; a policy's own label and group are ReadPolicies' concern.
        if (first || (other.perturbation == k && (other.policy == p || (other.group && group)))) continue;
        const auto key = nodes[p].Optional(group ? "seed_group" : "label");
        (key ? *key : nodes[p])
            .Fail("'" + name + "' names both " + describe(other) + " and " + describe(use) +
                  ": their cells would share one id and the sweep could never finish; rename one");
      }
    }
  }
}

void ReadPolicies(const YamlValue& root, const std::vector<std::string>& known_robots, const std::string& config_dir,
                  PolicyFiles files, SweepSpec& spec) {
  const auto single = root.Optional("policy");
  const auto several = root.Optional("policies");
  if (single.has_value() == several.has_value()) root.Fail("needs exactly one of policy: {...} and policies: [...]");
  if (single) {
    spec.policies.push_back(ReadPolicySpec(*single, false, known_robots, config_dir, files));
    RequireFilterSelectsCells(*single, spec.policies.back(), spec);
    return;
  }
  const std::vector<YamlValue> entries = several->Elements();
  if (entries.empty()) several->Fail("must name at least one policy, got []");
  for (const YamlValue& entry : entries) {
    PolicySpec policy = ReadPolicySpec(entry, true, known_robots, config_dir, files);
    RequireFilterSelectsCells(entry, policy, spec);
    for (const PolicySpec& other : spec.policies) {
      if (other.label == policy.label) entry.Required("label").Fail("'" + policy.label + "' is used twice");
      if (other.label == policy.seed_group || other.seed_group == policy.label) {
        entry.Fail("a label and a seed group share the name '" +
                   (other.label == policy.seed_group ? other.label : policy.label) + "'");
      }
    }
    spec.policies.push_back(std::move(policy));
  }
}

// figures.galt_reference_datasets: {task: DIR} for the sweep's TAVIS-Head tasks, each DIR a
// LeRobot dataset (relative paths from the current directory, as match_dataset). Checked here for
// its meta/info.json, so that a mistyped path stops the sweep before it runs; its GALT is read
// when the results are written (galt_reference.h).
nlohmann::ordered_json ReadGaltReferenceDatasets(const YamlValue& datasets,
                                                 const std::vector<std::string>& sweep_tasks) {
  nlohmann::ordered_json json = nlohmann::ordered_json::object();
  for (const scenarios::Suite suite : scenarios::kAllSuites) {
    for (const scenarios::ScenarioDef* task : scenarios::SuiteScenarios(suite)) {
      const auto dir = datasets.Optional(task->name);
      if (!dir) continue;
      if (suite != scenarios::Suite::kTavisHead) dir->Fail("Figure 4 draws TAVIS-Head tasks only, not " + task->name);
      if (std::find(sweep_tasks.begin(), sweep_tasks.end(), task->name) == sweep_tasks.end()) {
        dir->Fail("the sweep does not evaluate " + task->name);
      }
      const std::string path = dir->AsString();
      if (!std::filesystem::is_regular_file(std::filesystem::path(path) / "meta" / "info.json")) {
        dir->Fail("'" + path + "' is not a LeRobot dataset (no meta/info.json there)");
      }
      json[task->name] = path;
    }
  }
  datasets.ExpectNoOtherKeys();  // names no task
  if (json.empty()) datasets.Fail("must map at least one TAVIS-Head task to a dataset folder");
  return json;
}

// figures: names labels (or seed groups) for the paper's figures; checked against the policies.
void ReadFigures(const YamlValue& figures, SweepSpec& spec) {
  const auto known = [&spec](const YamlValue& value) {
    const std::string name = value.AsString();
    for (const PolicySpec& policy : spec.policies) {
      if (policy.label == name || policy.seed_group == name) return name;
    }
    std::string labels;
    for (const PolicySpec& policy : spec.policies) labels += (labels.empty() ? "" : ", ") + policy.label;
    value.Fail("no policy has the label or seed group '" + name + "' (labels: " + labels + ")");
    return name;
  };
  RejectUnknownKeys(figures, {"policy", "head_vs_fixed", "splits", "galt", "galt_reference", "single_vs_multi",
                              "ablation", "galt_reference_datasets", "galt_window_s"});
  nlohmann::ordered_json json = nlohmann::ordered_json::object();
  for (const char* key : {"policy", "head_vs_fixed", "splits", "galt", "galt_reference"}) {
    if (const auto value = figures.Optional(key)) json[key] = known(*value);
  }
  if (const auto pair = figures.Optional("single_vs_multi")) {
    const std::vector<YamlValue> names = pair->Elements();
    if (names.size() != 2)
      pair->Fail("must name two labels or seed groups (single-task, multi-task), got " + pair->Text());
    json["single_vs_multi"] = {known(names[0]), known(names[1])};
  }
  if (const auto ablation = figures.Optional("ablation")) {
    for (const char* arm : {"no_av", "full_av", "wrist_only"}) {
      const YamlValue entry = ablation->Required(arm);
      nlohmann::ordered_json arm_json = {{"label", known(entry.Required("label"))}};
      arm_json["task"] = entry.String("task");
      try {
        scenarios::FindScenario(arm_json["task"]);
      } catch (const std::invalid_argument& error) {
        entry.Required("task").Fail(error.what());
      }
      const std::string camera = entry.String("camera");
      try {
        ParseCameraProtocol(camera);
      } catch (const std::invalid_argument& error) {
        entry.Required("camera").Fail(error.what());
      }
      arm_json["camera"] = camera;
      entry.ExpectNoOtherKeys();
      json["ablation"][arm] = arm_json;
    }
    ablation->ExpectNoOtherKeys();
  }
  if (const auto datasets = figures.Optional("galt_reference_datasets")) {
    if (json.contains("galt_reference"))
      datasets->Fail("names Figure 4's reference as well as galt_reference; give one of them");
    json["galt_reference_datasets"] = ReadGaltReferenceDatasets(*datasets, spec.tasks);
  }
  if (const auto window = figures.Optional("galt_window_s")) {
    json["galt_window_s"] = window->AsDouble({0.5, 4.0, false, "s", " (the detector keeps GALT in [-0.5, 4.0] s)"});
  }
  figures.ExpectNoOtherKeys();
  spec.figures = json;
}

// perturbations: [none, camera:fov-wide, sensor:noise-low+lighting:dim]; every level is looked up
// in config_dir's perturbation files now, so a typo fails before any cell runs.
std::vector<std::vector<std::string>> ReadPerturbations(const YamlValue& list, const std::string& config_dir) {
  if (!list.IsSequence() || list.Elements().empty())
    list.Fail("must be a non-empty list (none, AXIS:LEVEL or AXIS:LEVEL+AXIS:LEVEL), got " + list.Text());
  std::vector<std::vector<std::string>> sets;
  std::vector<std::string> texts;  // each set as written, for messages
  for (const YamlValue& entry : list.Elements()) {
    std::vector<std::string> choices;
    try {
      choices = SplitPerturbationSet(entry.AsString());
      perturb::ResolvePerturbations(config_dir, choices);
    } catch (const std::invalid_argument& error) {
      entry.Fail(error.what());
    } catch (const configs::ConfigError& error) {
      entry.Fail(error.what());
    }
    for (std::size_t i = 0; i < sets.size(); ++i) {
      if (perturb::PerturbationLabelSuffix(sets[i]) == perturb::PerturbationLabelSuffix(choices))
        entry.Fail(entry.Text() + " is listed twice");
      // The same levels in another order are the same scene: they would run as a second label.
      std::vector<std::string> earlier = sets[i];
      std::vector<std::string> these = choices;
      std::sort(earlier.begin(), earlier.end());
      std::sort(these.begin(), these.end());
      if (earlier == these) {
        entry.Fail(entry.Text() + " is " + texts[i] + " (perturbations[" + std::to_string(i) +
                   "]) in another order; list each combination once");
      }
    }
    sets.push_back(std::move(choices));
    texts.push_back(entry.Text());
  }
  return sets;
}

SweepSpec ReadSpec(const YamlValue& root, const std::string& source, const std::string& config_dir, PolicyFiles files) {
  SweepSpec spec;
  spec.source = source;
  RejectUnknownKeys(root, {"suites", "tasks", "robots", "splits", "cameras", "seeds", "episodes", "envs", "videos",
                           "policy", "policies", "perturbations", "figures", "sequential"});
  const auto suites = root.Optional("suites");
  const auto tasks = root.Optional("tasks");
  if (!suites && !tasks) root.Fail("needs suites: [...] or tasks: [...] (or both)");
  spec.tasks = ReadTasks(suites, tasks, &spec.suites);
  const std::vector<std::string> known_robots = configs::KnownRobots(config_dir);
  spec.robots = ReadRobots(root.Required("robots"), known_robots);
  spec.splits = ReadSplits(root.Required("splits"));
  spec.cameras = ReadCameras(root.Required("cameras"));
  const YamlValue seeds = root.Required("seeds");
  if (seeds.Elements().empty()) seeds.Fail("must name at least one, got []");
  for (const YamlValue& seed : seeds.Elements()) {
    const uint64_t value = ReadSeed(seed);
    if (std::find(spec.seeds.begin(), spec.seeds.end(), value) != spec.seeds.end())
      seed.Fail(seed.Text() + " is listed twice");
    spec.seeds.push_back(value);
  }
  spec.episodes = ReadSettingCount(root.Required("episodes"), "episodes");
  if (const auto envs = root.Optional("envs")) spec.envs = ReadSettingCount(*envs, "envs");
  if (const auto videos = root.Optional("videos")) spec.videos = ReadCount(*videos, 0, spec.episodes);
  ReadPolicies(root, known_robots, config_dir, files, spec);
  if (const auto perturbations = root.Optional("perturbations"))
    spec.perturbations = ReadPerturbations(*perturbations, config_dir);
  RequireDistinctCellLabels(root, spec);
  if (const auto figures = root.Optional("figures")) ReadFigures(*figures, spec);
  if (const auto sequential = root.Optional("sequential")) spec.sequential = ReadSequential(*sequential, spec);
  root.ExpectNoOtherKeys();
  return spec;
}

}  // namespace

SweepSpec ParseSweepSpec(const std::string& yaml_text, const std::string& source_name, const std::string& config_dir,
                         PolicyFiles files) {
  return ReadSpec(YamlValue::LoadString(yaml_text, source_name), source_name, config_dir, files);
}

SweepSpec LoadSweepSpec(const std::string& path, const std::string& config_dir, PolicyFiles files) {
  return ReadSpec(YamlValue::LoadFile(path), path, config_dir, files);
}

nlohmann::ordered_json SweepSpecJson(const SweepSpec& spec) {
  nlohmann::ordered_json splits = nlohmann::ordered_json::array();
  for (const scenarios::Split split : spec.splits) splits.push_back(scenarios::ToString(split));
  nlohmann::ordered_json cameras = nlohmann::ordered_json::array();
  for (const CameraProtocol camera : spec.cameras) cameras.push_back(ToString(camera));
  nlohmann::ordered_json policies = nlohmann::ordered_json::array();
  for (const PolicySpec& policy : spec.policies) policies.push_back(PolicySpecJson(policy));
  nlohmann::ordered_json json = {{"suites", spec.suites},     {"tasks", spec.tasks},  {"robots", spec.robots},
                                 {"splits", splits},          {"cameras", cameras},   {"seeds", spec.seeds},
                                 {"episodes", spec.episodes}, {"policies", policies}, {"figures", spec.figures}};
  if (spec.videos > 0) json["videos"] = spec.videos;  // absent otherwise, as in manifests written before it existed
  // Absent for the base scene alone, as in manifests written before perturbations existed.
  if (spec.perturbations != std::vector<std::vector<std::string>>{{}}) {
    nlohmann::ordered_json sets = nlohmann::ordered_json::array();
    for (const std::vector<std::string>& choices : spec.perturbations) sets.push_back(choices);
    json["perturbations"] = sets;
  }
  // Absent when off, as in manifests written before it existed.
  if (spec.sequential.enabled) json["sequential"] = report::SequentialSettingsJson(spec.sequential);
  return json;
}

std::vector<SweepCell> ExpandCells(const SweepSpec& spec, const std::string& config_dir) {
  std::vector<SweepCell> cells;
  for (const std::string& task : spec.tasks) {
    for (const std::string& robot : spec.robots) {
      for (const scenarios::Split split : spec.splits) {
        for (const CameraProtocol camera : spec.cameras) {
          for (const PolicySpec& policy : spec.policies) {
            for (const std::vector<std::string>& perturbations : spec.perturbations) {
              for (const uint64_t seed : spec.seeds) {
                SweepCell cell;
                cell::EvaluationCellConfig& config = cell.config;
                config.task = task;
                config.robot = robot;
                config.split = split;
                config.camera = camera;
                config.seed = seed;
                config.episodes = spec.episodes;
                config.envs = spec.envs;
                config.config_dir = config_dir;
                config.perturbations = perturbations;
                if (!policy.Serves(config)) continue;
                policy.ApplyTo(config);
                const std::string suffix = perturb::PerturbationLabelSuffix(perturbations);
                cell.label = policy.label + suffix;
                cell.seed_group = policy.seed_group.empty() ? "" : policy.seed_group + suffix;
                cell.id = cell::CellFolderName(config, policy.label, cell::PerturbationsIn::kLabel);
                cells.push_back(std::move(cell));
              }
            }
          }
        }
      }
    }
  }
  return cells;
}

std::vector<std::string> SplitPerturbationSet(const std::string& text) {
  if (text == "none") return {};
  std::vector<std::string> choices;
  std::size_t start = 0;
  while (true) {
    const std::size_t plus = text.find('+', start);
    const std::string choice = text.substr(start, plus == std::string::npos ? std::string::npos : plus - start);
    perturb::ParsePerturbationChoice(choice);
    choices.push_back(choice);
    if (plus == std::string::npos) break;
    start = plus + 1;
  }
  return choices;
}

Shard ParseShard(const std::string& text) {
  const std::size_t slash = text.find('/');
  const auto number = [&text](const std::string& part) {
    if (part.empty() || part.size() > 9 ||
        !std::all_of(part.begin(), part.end(), [](unsigned char c) { return std::isdigit(c) != 0; })) {
      throw output::SettingError("shard", "must be I/N with 0 <= I < N (e.g. 0/3), got '" + text + "'");
    }
    return std::stoi(part);
  };
  if (slash == std::string::npos) number("");
  const Shard shard{number(text.substr(0, slash)), number(text.substr(slash + 1))};
  if (shard.count < 1 || shard.index >= shard.count) {
    throw output::SettingError("shard", "must be I/N with 0 <= I < N (e.g. 0/3), got '" + text + "'");
  }
  return shard;
}

void RequireShardHoldsCells(const Shard& shard, std::size_t cells) {
  if (static_cast<std::size_t>(shard.count) <= cells) return;
  const std::string text = std::to_string(shard.index) + "/" + std::to_string(shard.count);
  throw output::SettingError("shard", "'" + text + "' splits the sweep's " + std::to_string(cells) + " cell" +
                                          (cells == 1 ? "" : "s") + " into " + std::to_string(shard.count) +
                                          " shards: N must be 1 to " + std::to_string(cells) +
                                          ", so that every shard runs a cell");
}

bool InShard(std::size_t cell_position, const Shard& shard) {
  return cell_position % static_cast<std::size_t>(shard.count) == static_cast<std::size_t>(shard.index);
}

}  // namespace tavis::batch::sweep

#include "batch/report/results_table.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include <nlohmann/json.hpp>

#include "batch/camera_protocol.h"
#include "batch/cell/statistics.h"
#include "scenarios/registry.h"

namespace tavis::batch::report {
namespace {

std::string SuiteTitle(const std::string& suite) { return scenarios::Title(scenarios::ParseSuite(suite)); }

// The reference writes task and split names in snake_case, this project in kebab-case.
std::string KebabCase(std::string name) {
  std::replace(name.begin(), name.end(), '_', '-');
  return name;
}

// "headcam"/"fixedcam" are the reference's spellings of the camera modes "head"/"fixed".
std::string CameraMode(std::string name) {
  const std::string suffix = "cam";
  const bool has_suffix =
      name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
  if (has_suffix) name.resize(name.size() - suffix.size());
  return name;
}

std::string ReadString(const nlohmann::json& summary, const char* key, const std::string& source) {
  const auto it = summary.find(key);
  if (it == summary.end()) throw std::runtime_error(source + ": missing key '" + key + "'");
  if (!it->is_string() || it->get<std::string>().empty()) {
    throw std::runtime_error(source + ": key '" + key + "' must be a non-empty string, got " + it->dump());
  }
  return it->get<std::string>();
}

// Bounded so that the pooled sums of any number of cells cannot overflow 64 bits in practice.
constexpr int64_t kMaxCount = int64_t{1} << 48;

int64_t ReadCount(const nlohmann::json& summary, const char* key, const std::string& source) {
  const auto it = summary.find(key);
  if (it == summary.end()) throw std::runtime_error(source + ": missing key '" + key + "'");
  if (!it->is_number_integer() || it->get<int64_t>() < 0 || it->get<int64_t>() > kMaxCount) {
    throw std::runtime_error(source + ": key '" + key + "' must be an integer from 0 to " + std::to_string(kMaxCount) +
                             ", got " + it->dump());
  }
  return it->get<int64_t>();
}

// A summary's seed as the text of its number: a string of digits ("7", as some scripts write it)
// is the same seed as the number 7, so a copied cell cannot pass as another seed that way.
std::string SeedText(const nlohmann::json& seed, const std::string& source) {
  if (seed.is_number_unsigned() || (seed.is_number_integer() && seed.get<int64_t>() >= 0)) return seed.dump();
  if (seed.is_string()) {
    const std::string text = seed.get<std::string>();
    if (!text.empty() && text.size() <= 20 &&
        std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; })) {
      try {
        return std::to_string(std::stoull(text));
      } catch (const std::out_of_range&) {
      }
    }
  }
  if (seed.is_null()) return "";
  throw std::runtime_error(source + ": key 'seed' must be an integer from 0 to 2^64-1, got " + seed.dump());
}

// A summary's perturbation levels ("camera:tilt-15"), sorted: the order they were given in does not
// change the cell.
std::vector<std::string> ReadPerturbations(const nlohmann::json& levels, const std::string& source) {
  const auto bad = [&] {
    return std::runtime_error(source + ": key 'perturbations' must be a list of \"AXIS:LEVEL\" strings, got " +
                              levels.dump());
  };
  if (!levels.is_array()) throw bad();
  std::vector<std::string> names;
  for (const nlohmann::json& level : levels) {
    if (!level.is_string() || level.get<std::string>().empty()) throw bad();
    names.push_back(level.get<std::string>());
  }
  std::sort(names.begin(), names.end());
  return names;
}

// Reads a cell's episodes.jsonl into `cell` (has_records, records_digest, record_keys and their
// successes) and checks it against the summary's counts: the records are what the counts claim to
// summarise.
void ReadRecords(const std::filesystem::path& path, CellCounts& cell) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot open file");
  std::vector<std::string> lines;
  std::vector<std::tuple<uint64_t, int64_t, bool>> keyed;  // (seed, episode, success)
  int64_t episodes = 0, successes = 0, line_number = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::string where = path.string() + ":" + std::to_string(line_number);
    const nlohmann::json record = nlohmann::json::parse(line, nullptr, false);
    if (record.is_discarded() || !record.is_object())
      throw std::runtime_error(where + ": not a JSON object (a damaged record)");
    const auto success = record.find("success");
    if (success == record.end() || !success->is_boolean()) {
      throw std::runtime_error(where + ": a record needs \"success\": true or false");
    }
    ++episodes;
    if (success->get<bool>()) ++successes;
    const auto seed = record.find("seed"), episode = record.find("episode");
    if (seed != record.end() && seed->is_number_unsigned() && episode != record.end() && episode->is_number_integer()) {
      keyed.emplace_back(seed->get<uint64_t>(), episode->get<int64_t>(), success->get<bool>());
    }
    lines.push_back(record.dump());  // keys sorted: the same record however it was spaced
  }
  if (episodes != cell.n_episodes || successes != cell.n_successful) {
    throw std::runtime_error("cell " + path.parent_path().string() + ": episodes.jsonl holds " +
                             std::to_string(episodes) + " episodes (" + std::to_string(successes) +
                             " successful) but summary.json says n_episodes " + std::to_string(cell.n_episodes) +
                             ", n_successful " + std::to_string(cell.n_successful));
  }
  std::sort(keyed.begin(), keyed.end());
  for (const auto& [seed, episode, succeeded] : keyed) {
    cell.record_keys.emplace_back(seed, episode);
    cell.record_successes.push_back(succeeded);
  }
  const auto twice = std::adjacent_find(cell.record_keys.begin(), cell.record_keys.end());
  if (twice != cell.record_keys.end()) {
    throw std::runtime_error(path.string() + ": holds episode " + std::to_string(twice->second) + " of seed " +
                             std::to_string(twice->first) + " twice");
  }
  std::sort(lines.begin(), lines.end());
  std::string all;
  for (const std::string& line : lines) all += line + "\n";
  cell.has_records = true;
  cell.records_digest = std::hash<std::string>{}(all);
}

// tavis's temporary folders beside a result it replaces (output_folder.h's output::OutputReplacement):
// ".NAME.tavis-new-PID" (being built) and ".NAME.tavis-old-PID" (being removed).
bool IsTemporaryOutputFolder(const std::filesystem::path& dir) {
  const std::string name = dir.filename().string();
  return name.size() > 1 && name[0] == '.' &&
         (name.find(".tavis-new-") != std::string::npos || name.find(".tavis-old-") != std::string::npos);
}

// Cells of one (task, robot, split, camera, label): files within such a group must not hold the
// same cell twice.
using CellGroup = std::tuple<std::string, std::string, std::string, std::string, std::string>;

CellGroup GroupOf(const CellCounts& cell) { return {cell.task, cell.robot, cell.split, cell.camera, cell.label}; }

// Throws naming both files when `cell` repeats an earlier cell of its group: the same seed in
// the summaries, the same records, or an episode of a seed that an earlier file holds too.
class DuplicateCellCheck {
 public:
  void Add(const CellCounts& cell) {
    const CellGroup group = GroupOf(cell);
    const std::string what = "(task " + cell.task + ", robot " + cell.robot + ", split " + cell.split + ", camera " +
                             cell.camera + ", label " + cell.label + ")";
    if (!cell.seed.empty()) {
      const auto [it, inserted] = seeds_.emplace(std::make_pair(group, cell.seed), cell.source);
      if (!inserted) {
        throw std::runtime_error("duplicate cell (same task, robot, split, camera, seed and label): " + it->second +
                                 " and " + cell.source);
      }
    }
    if (!cell.has_records) return;
    const auto [it, inserted] = digests_.emplace(std::make_pair(group, cell.records_digest), cell.source);
    if (!inserted) {
      throw std::runtime_error("duplicate cell " + what + ": " + it->second + " and " + cell.source +
                               " hold the same episode records, whatever their summaries say about the seed");
    }
    for (const auto& [seed, episode] : cell.record_keys) {
      const auto [earlier, new_episode] = episodes_.emplace(std::make_tuple(group, seed, episode), cell.source);
      if (!new_episode) {
        throw std::runtime_error("duplicate episodes " + what + ": " + earlier->second + " and " + cell.source +
                                 " both hold episode " + std::to_string(episode) + " of seed " + std::to_string(seed));
      }
    }
  }

 private:
  std::map<std::pair<CellGroup, std::string>, std::string> seeds_;
  std::map<std::pair<CellGroup, std::size_t>, std::string> digests_;
  std::map<std::tuple<CellGroup, uint64_t, int64_t>, std::string> episodes_;
};

// Throws naming `source` unless `name` (of `key`) is one of `known`.
void RequireKnown(const std::string& name, const char* key, const std::vector<std::string>& known,
                  const std::string& source) {
  if (std::find(known.begin(), known.end(), name) != known.end()) return;
  std::string list;
  for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
  throw std::runtime_error(source + ": unknown " + key + " '" + name + "' (known: " + list + ")");
}

const std::vector<std::string>& KnownTaskNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> all;
    for (const scenarios::ScenarioDef& scenario : scenarios::AllScenarios()) all.push_back(scenario.name);
    return all;
  }();
  return names;
}

const std::vector<std::string>& KnownSplitNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> all;
    for (const scenarios::Split split : scenarios::kAllSplits) all.push_back(scenarios::ToString(split));
    return all;
  }();
  return names;
}

// Sort key: the position in `known`, names not in it after all known ones, alphabetically.
std::pair<std::size_t, std::string> OrderKey(const std::string& name, const std::vector<std::string>& known) {
  const auto it = std::find(known.begin(), known.end(), name);
  return {static_cast<std::size_t>(it - known.begin()), name};
}

// Columns: robots by name, then splits and camera modes in the paper's order.
bool ColumnBefore(const TableColumn& a, const TableColumn& b) {
  static const std::vector<std::string> robots;  // none known: alphabetical
  static const std::vector<std::string> splits = [] {
    std::vector<std::string> names;
    for (const scenarios::Split split : scenarios::kAllSplits) names.push_back(scenarios::ToString(split));
    return names;
  }();
  static const std::vector<std::string>& cameras = CameraProtocolNames();
  return std::make_tuple(OrderKey(a.robot, robots), OrderKey(a.split, splits), OrderKey(a.camera, cameras)) <
         std::make_tuple(OrderKey(b.robot, robots), OrderKey(b.split, splits), OrderKey(b.camera, cameras));
}

bool SameColumn(const TableColumn& a, const TableColumn& b) {
  return a.robot == b.robot && a.split == b.split && a.camera == b.camera;
}

std::string Percent(double fraction) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f", 100.0 * fraction);
  return text;
}

// The strings of one table row, each cell as (rate, ci_low, ci_high); empty strings where a
// value is absent, so the Markdown and CSV writers share one source of numbers.
struct FormattedCell {
  std::string rate;
  std::string ci_low;
  std::string ci_high;
};

FormattedCell FormatRate(const std::optional<RateCell>& cell) {
  if (!cell) return {};
  const cell::ProportionInterval interval = cell::WilsonInterval(cell->n_successful, cell->n_episodes);
  return {Percent(cell->rate()), Percent(interval.low), Percent(interval.high)};
}

struct FormattedRow {
  std::string label;
  std::vector<FormattedCell> cells;
};

std::vector<FormattedRow> FormatRows(const ResultsTable& table) {
  const std::string title = SuiteTitle(table.suite);
  std::vector<FormattedRow> rows;
  for (std::size_t t = 0; t < table.tasks.size(); ++t) {
    FormattedRow row{table.tasks[t], {}};
    for (const std::optional<RateCell>& cell : table.cells[t]) {
      row.cells.push_back(FormatRate(cell));
    }
    rows.push_back(std::move(row));
  }
  FormattedRow average{title + " mean (task average)", {}};
  for (const std::optional<double>& rate : table.task_average) {
    average.cells.push_back(rate ? FormattedCell{Percent(*rate), "", ""} : FormattedCell{});
  }
  rows.push_back(std::move(average));
  FormattedRow pooled{title + " mean (pooled over episodes)", {}};
  for (const std::optional<RateCell>& cell : table.pooled) {
    pooled.cells.push_back(FormatRate(cell));
  }
  rows.push_back(std::move(pooled));
  return rows;
}

}  // namespace

std::vector<std::string> SuiteTasks(const std::string& suite) {
  std::vector<std::string> tasks;
  for (const scenarios::ScenarioDef* scenario : scenarios::SuiteScenarios(scenarios::ParseSuite(suite))) {
    tasks.push_back(scenario->name);
  }
  return tasks;
}

CellCounts ReadCellResult(const std::filesystem::path& path, const std::vector<std::string>& known_robots) {
  const std::string source = path.string();
  std::ifstream in(path);
  if (!in) throw std::runtime_error(source + ": cannot open file");
  nlohmann::json summary;
  try {
    in >> summary;
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(source + ": invalid JSON: " + e.what());
  }
  if (!summary.is_object()) throw std::runtime_error(source + ": expected a JSON object");

  CellCounts cell;
  cell.source = source;
  cell.task = KebabCase(ReadString(summary, "task", source));
  cell.robot = ReadString(summary, "robot", source);
  cell.split = KebabCase(ReadString(summary, "split", source));
  if (summary.contains("camera")) cell.camera = CameraMode(ReadString(summary, "camera", source));
  if (summary.contains("policy")) cell.policy = ReadString(summary, "policy", source);
  if (summary.contains("seed")) cell.seed = SeedText(summary.at("seed"), source);
  if (summary.contains("perturbations")) cell.perturbations = ReadPerturbations(summary["perturbations"], source);
  RequireKnown(cell.task, "task", KnownTaskNames(), source);
  if (!known_robots.empty()) RequireKnown(cell.robot, "robot", known_robots, source);
  RequireKnown(cell.split, "split", KnownSplitNames(), source);
  RequireKnown(cell.camera, "camera", CameraProtocolNames(), source);
  cell.n_episodes = ReadCount(summary, "n_episodes", source);
  cell.n_successful = ReadCount(summary, "n_successful", source);
  if (cell.n_successful > cell.n_episodes) {
    throw std::runtime_error(source + ": n_successful = " + std::to_string(cell.n_successful) +
                             " exceeds n_episodes = " + std::to_string(cell.n_episodes));
  }
  const std::filesystem::path records = path.parent_path() / "episodes.jsonl";
  if (std::filesystem::exists(records)) ReadRecords(records, cell);
  return cell;
}

std::vector<std::filesystem::path> FindCellSummaries(const std::filesystem::path& folder) {
  if (!std::filesystem::is_directory(folder)) {
    throw std::runtime_error(folder.string() + ": not a directory");
  }
  std::vector<std::filesystem::path> paths;
  for (auto entry = std::filesystem::recursive_directory_iterator(folder);
       entry != std::filesystem::recursive_directory_iterator(); ++entry) {
    if (entry->is_directory() && IsTemporaryOutputFolder(entry->path())) entry.disable_recursion_pending();
    const bool sweep_summary = std::filesystem::exists(entry->path().parent_path() / "manifest.json");
    if (entry->is_regular_file() && entry->path().filename() == "summary.json" && !sweep_summary) {
      paths.push_back(entry->path());
    }
  }
  std::sort(paths.begin(), paths.end());
  return paths;
}

std::vector<CellCounts> LoadCellResults(const std::filesystem::path& folder,
                                        const std::vector<std::string>& known_robots, const CellLabeller& label_of) {
  const std::vector<std::filesystem::path> paths = FindCellSummaries(folder);
  std::vector<CellCounts> cells;
  cells.reserve(paths.size());
  // A copied cell folder would count its episodes twice and narrow the interval. Files without a
  // seed or records (the reference's) cannot be told apart from other seeds of the cell, so they are pooled.
  DuplicateCellCheck duplicates;
  for (const std::filesystem::path& path : paths) {
    CellCounts cell = ReadCellResult(path, known_robots);
    cell.label = label_of ? label_of(cell) : cell.policy;
    duplicates.Add(cell);
    cells.push_back(std::move(cell));
  }
  return cells;
}

ResultsTable BuildResultsTable(const std::vector<CellCounts>& cells, const std::string& suite) {
  ResultsTable table;
  table.suite = suite;
  table.tasks = SuiteTasks(suite);

  // Pool the suite's cells per (task, column); cells without episodes count as not evaluated.
  using CellKey = std::tuple<std::size_t, std::string, std::string, std::string>;
  const auto key_of = [](std::size_t task, const TableColumn& column) {
    return CellKey{task, column.robot, column.split, column.camera};
  };
  std::map<CellKey, RateCell> pooled_by_key;
  const CellCounts* policy_source = nullptr;
  for (const CellCounts& cell : cells) {
    const auto task = std::find(table.tasks.begin(), table.tasks.end(), cell.task);
    if (task == table.tasks.end()) continue;
    if (cell.n_episodes == 0) {
      table.skipped_empty.push_back(cell.source);
      continue;
    }
    if (policy_source && policy_source->policy != cell.policy) {
      throw std::runtime_error("cells of one table name different policies: '" + policy_source->policy + "' in " +
                               policy_source->source + ", '" + cell.policy + "' in " + cell.source);
    }
    policy_source = &cell;
    const TableColumn column{cell.robot, cell.split, cell.camera};
    if (std::none_of(table.columns.begin(), table.columns.end(),
                     [&](const TableColumn& c) { return SameColumn(c, column); })) {
      table.columns.push_back(column);
    }
    RateCell& pooled = pooled_by_key[key_of(static_cast<std::size_t>(task - table.tasks.begin()), column)];
    pooled.n_successful += cell.n_successful;
    pooled.n_episodes += cell.n_episodes;
  }
  if (table.columns.empty()) throw std::runtime_error("no cell results for suite " + suite);
  std::sort(table.columns.begin(), table.columns.end(), ColumnBefore);

  table.cells.assign(table.tasks.size(), std::vector<std::optional<RateCell>>(table.columns.size()));
  table.task_average.resize(table.columns.size());
  table.pooled.resize(table.columns.size());
  for (std::size_t c = 0; c < table.columns.size(); ++c) {
    double rate_sum = 0.0;
    int tasks_present = 0;
    RateCell pooled;
    for (std::size_t t = 0; t < table.tasks.size(); ++t) {
      const auto it = pooled_by_key.find(key_of(t, table.columns[c]));
      if (it == pooled_by_key.end()) continue;
      table.cells[t][c] = it->second;
      rate_sum += it->second.rate();
      ++tasks_present;
      pooled.n_successful += it->second.n_successful;
      pooled.n_episodes += it->second.n_episodes;
    }
    table.task_average[c] = rate_sum / tasks_present;
    table.pooled[c] = pooled;
  }
  return table;
}

std::string FormatMarkdown(const ResultsTable& table, bool with_intervals) {
  std::ostringstream out;
  out << "**" << SuiteTitle(table.suite) << "**: success rate (%)" << (with_intervals ? " [95% Wilson interval]" : "")
      << "\n\n";
  out << "| task |";
  for (const TableColumn& column : table.columns) out << " " << column.label() << " |";
  out << "\n|:---|";
  for (std::size_t c = 0; c < table.columns.size(); ++c) out << "---:|";
  out << "\n";
  for (const FormattedRow& row : FormatRows(table)) {
    out << "| " << row.label << " |";
    for (const FormattedCell& cell : row.cells) {
      if (cell.rate.empty()) {
        out << " - |";
      } else if (with_intervals && !cell.ci_low.empty()) {
        out << " " << cell.rate << " [" << cell.ci_low << ", " << cell.ci_high << "] |";
      } else {
        out << " " << cell.rate << " |";
      }
    }
    out << "\n";
  }
  // The suite means of a column without every task are easy to misread: name those columns.
  std::string incomplete;
  for (std::size_t c = 0; c < table.columns.size(); ++c) {
    const auto evaluated =
        std::count_if(table.cells.begin(), table.cells.end(), [c](const auto& row) { return row[c].has_value(); });
    if (static_cast<std::size_t>(evaluated) == table.tasks.size()) continue;
    incomplete += (incomplete.empty() ? "" : "; ") + table.columns[c].label() + " (" + std::to_string(evaluated) +
                  " of " + std::to_string(table.tasks.size()) + " tasks)";
  }
  if (!incomplete.empty()) {
    out << "\nSuite means over the evaluated tasks only: " << incomplete << ".\n";
  }
  return out.str();
}

std::string FormatCsv(const ResultsTable& table, bool with_intervals) {
  std::ostringstream out;
  out << "task";
  for (const TableColumn& column : table.columns) {
    out << "," << column.label();
    if (with_intervals) {
      out << "," << column.label() << " ci_low," << column.label() << " ci_high";
    }
  }
  out << "\n";
  for (const FormattedRow& row : FormatRows(table)) {
    out << row.label;
    for (const FormattedCell& cell : row.cells) {
      out << "," << cell.rate;
      if (with_intervals) out << "," << cell.ci_low << "," << cell.ci_high;
    }
    out << "\n";
  }
  return out.str();
}

}  // namespace tavis::batch::report

// Success-rate tables in the paper's layout, built from a folder of evaluation-cell results.
//
// Input: every file named `summary.json` under a folder (recursively). Keys read:
//   task          "clutter-pick-cube" (reference snake_case names are accepted too)
//   robot         "gr1t2" | "reachy2" | any other name
//   split         "id" | "ood-spatial" | "ood-init-pose" (snake_case accepted)
//   camera        optional, "head" (default when absent) | "fixed" | any other name
//   policy        optional; all cells of one table must name the same policy
//   n_episodes, n_successful   integers, 0 <= n_successful <= n_episodes
// Other keys are ignored. Cells with the same (task, robot, split, camera), e.g. several seeds,
// are pooled by summing their counts.
//
// A cell folder that also holds `episodes.jsonl` (as `tavis eval` writes it) is checked against
// it: its records must number n_episodes with n_successful of them successful, and no two files
// of one (task, robot, split, camera, label) may hold the same records (the same set of lines, or
// the same episode of the same seed): a copied cell would count its episodes twice whatever its
// summary says about its seed. A `summary.json` beside a `manifest.json` is a sweep's results
// summary, not a cell, and tavis's temporary folders (".NAME.tavis-new-PID", ".NAME.tavis-old-PID")
// are not read.
//
// Layout: one row per task of the suite, in suite order, then two suite-mean rows: the plain
// average of the task success rates ("task average", what the paper's text calls the suite
// mean, no interval) and the rate pooled over all episodes of the suite ("pooled", with the
// Wilson interval of the pooled counts, as the reference's AVERAGE row, spec 10.4). Columns are
// robot x split x camera, only the combinations present, in the order gr1t2, reachy2 / id,
// ood-spatial, ood-init-pose / head, fixed, other names sorted after the known ones.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace tavis::batch::report {

// One summary.json's counts. (Not evaluation_cell.h's cell::CellResult: two classes of one name in
// one namespace break the one-definition rule and crash in their destructors.)
struct CellCounts {
  std::string task;
  std::string robot;
  std::string split;
  std::string camera = "head";
  std::string policy;  // empty when the file does not name one
  std::string seed;    // a JSON number's text (a string of digits counts as that number), empty when absent
  std::vector<std::string> perturbations;  // summary.json's "perturbations" ("axis:level"), sorted; none when absent
  int64_t n_episodes = 0;
  int64_t n_successful = 0;
  std::string source;  // file it came from, for error messages
  std::string label;   // the policy label cells are kept apart by (LoadCellResults: the policy by default)
  // From episodes.jsonl beside the summary, when there is one: a digest of its records (the set of
  // lines, canonical JSON) and the (seed, episode) pairs of the records that name both, sorted,
  // with each one's success (record_successes[i] is record_keys[i]'s).
  bool has_records = false;
  std::size_t records_digest = 0;
  std::vector<std::pair<uint64_t, int64_t>> record_keys;
  std::vector<bool> record_successes;
};

// The suite's tasks in table order (the task registry's); throws std::invalid_argument for an
// unknown suite, naming the known ones.
std::vector<std::string> SuiteTasks(const std::string& suite);

// Reads one summary.json (and the episodes.jsonl beside it, when there is one); throws
// std::runtime_error naming the file, the key and the value, or the cell and both counts when its
// records do not match its summary.
CellCounts ReadCellResult(const std::filesystem::path& path, const std::vector<std::string>& known_robots = {});

// Every cell's summary.json under `folder` (at any depth, `folder/summary.json` included), in
// path order: not a sweep's own summary (beside its manifest.json), nothing inside tavis's
// temporary folders. Throws std::runtime_error when `folder` is not a directory.
std::vector<std::filesystem::path> FindCellSummaries(const std::filesystem::path& folder);

// A cell's label: cells of different labels are kept apart by the duplicate check.
using CellLabeller = std::function<std::string(const CellCounts&)>;

// Every cell's summary.json under `folder`, in path order, labelled by `label_of` (default: the
// cell's policy). Each task, split and camera must be a known one, and the robot one of
// `known_robots` unless it is empty. Two files of the same cell (task, robot, split, camera,
// label) are an error naming both when they name the same seed or hold the same records (above);
// files without a seed or records (the reference's) are pooled.
std::vector<CellCounts> LoadCellResults(const std::filesystem::path& folder,
                                        const std::vector<std::string>& known_robots = {},
                                        const CellLabeller& label_of = nullptr);

struct TableColumn {
  std::string robot;
  std::string split;
  std::string camera;

  std::string label() const { return robot + " " + split + " " + camera; }
};

// One cell of the table: counts, or nothing when the combination was not evaluated.
struct RateCell {
  int64_t n_successful = 0;
  int64_t n_episodes = 0;

  double rate() const { return static_cast<double>(n_successful) / static_cast<double>(n_episodes); }
};

struct ResultsTable {
  std::string suite;
  std::vector<std::string> tasks;  // row labels, suite order
  std::vector<TableColumn> columns;
  std::vector<std::vector<std::optional<RateCell>>> cells;  // [task][column]
  // Per column; nullopt when no task of the suite has episodes in that column.
  std::vector<std::optional<double>> task_average;  // mean of the task rates present
  std::vector<std::optional<RateCell>> pooled;      // summed counts over the tasks present
  // Cells of the suite left out of the table because they hold no episodes (their files).
  std::vector<std::string> skipped_empty;
};

// Throws std::invalid_argument for an unknown suite, std::runtime_error when cells that would
// share a table disagree on the policy, or when no cell belongs to the suite.
ResultsTable BuildResultsTable(const std::vector<CellCounts>& cells, const std::string& suite);

// Rates in percent with one decimal, optionally followed by the 95% Wilson interval
// "[low, high]"; a missing cell is "-" in Markdown and empty in CSV. The CSV has one column per
// table column, plus "<label> ci_low" and "<label> ci_high" columns when intervals are on.
std::string FormatMarkdown(const ResultsTable& table, bool with_intervals);
std::string FormatCsv(const ResultsTable& table, bool with_intervals);

}  // namespace tavis::batch::report

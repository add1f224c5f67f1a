// `tavis table`: success-rate tables in the paper's layout from a folder of cell results.
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/report/failure_event_table.h"
#include "batch/report/gaze_table.h"
#include "batch/report/policy_label.h"
#include "batch/report/results_table.h"
#include "batch/report/stage_funnel_table.h"
#include "configs/robot_config.h"
#include "scenarios/suite.h"
#include "tools/commands.h"
#include "tools/option_parsing.h"

namespace tavis::tools {
namespace {

struct TableOptions {
  std::string in_dir;
  std::string suite;
  std::string out_prefix;
  bool no_intervals = false;
  std::string label;         // keep only the cells of this policy label
  bool pool_labels = false;  // declared: pool cells of different labels
};

// The cells the table pools: those of --label, or all of them when they share one label or
// --pool-labels declares the pooling; anything else is refused, naming the labels.
std::vector<batch::report::CellCounts> CellsOfOneLabel(const std::vector<batch::report::CellCounts>& cells,
                                                       const TableOptions& options) {
  std::map<std::string, int> counts;
  std::vector<batch::report::CellCounts> kept;
  for (const batch::report::CellCounts& cell : cells) {
    ++counts[cell.label];
    if (options.label.empty() || cell.label == options.label) kept.push_back(cell);
  }
  std::string labels;
  for (const auto& [label, n] : counts)
    labels += (labels.empty() ? "" : ", ") + label + " (" + std::to_string(n) + (n == 1 ? " cell)" : " cells)");
  if (!options.label.empty() && kept.empty()) {
    throw std::invalid_argument("--label " + options.label + ": no cell has this label (labels: " + labels + ")");
  }
  if (options.label.empty() && counts.size() > 1 && !options.pool_labels) {
    throw std::invalid_argument("the cells under " + options.in_dir + " come from " + std::to_string(counts.size()) +
                                " policy labels: " + labels +
                                "; choose one with --label L, or pass --pool-labels to pool them");
  }
  return kept;
}

void WriteFile(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  out.close();
  if (!out) throw std::runtime_error(path + ": cannot write file");
}

void RunTable(const TableOptions& options) {
  if (!options.label.empty() && options.pool_labels)
    throw std::invalid_argument("--label and --pool-labels exclude each other");
  // Two labels may evaluate the same cell and seed (two checkpoints): the label is part of the
  // duplicate check.
  const std::vector<batch::report::CellCounts> cells =
      CellsOfOneLabel(batch::report::LoadCellResults(options.in_dir, configs::KnownRobots(DefaultConfigDir()),
                                                     batch::report::PolicyLabelOf),
                      options);
  const batch::report::ResultsTable table = batch::report::BuildResultsTable(cells, options.suite);
  for (const std::string& source : table.skipped_empty) {
    std::cerr << "tavis table: note: " << source << " holds no episodes (n_episodes 0): left out of the table\n";
  }
  const bool with_intervals = !options.no_intervals;
  // --out results/tables/acceptance: the folder part is made if it is missing.
  const std::filesystem::path folder = std::filesystem::path(options.out_prefix).parent_path();
  std::error_code error;
  if (!folder.empty() && !std::filesystem::create_directories(folder, error) && error) {
    throw std::runtime_error("--out " + options.out_prefix + ": cannot create the folder " + folder.string() + ": " +
                             error.message());
  }
  WriteFile(options.out_prefix + ".md",
            batch::report::FormatMarkdown(table, with_intervals) + batch::report::FormatFunnelMarkdown(table, cells) +
                batch::report::FormatEventsMarkdown(cells) + batch::report::FormatGazeMarkdown(cells));
  WriteFile(options.out_prefix + ".csv", batch::report::FormatCsv(table, with_intervals));
  std::cout << "wrote " << options.out_prefix << ".md and " << options.out_prefix << ".csv (" << table.tasks.size()
            << " tasks x " << table.columns.size() << " columns)\n";
}

}  // namespace

void RegisterTableCommand(CLI::App& app) {
  auto options = std::make_shared<TableOptions>();
  CLI::App* command =
      app.add_subcommand("table", "Success-rate table (paper layout) from the summary.json files under a folder");
  command
      ->add_option("--in", options->in_dir,
                   "Folder searched recursively for cells' summary.json (eval cells, a sweep's folder)")
      ->required();
  command->add_option("--suite", options->suite, "Suite whose tasks form the rows: " + scenarios::KnownSuites())
      ->required();
  command
      ->add_option("--out", options->out_prefix,
                   "Output prefix: writes PREFIX.md, PREFIX.csv (its folder is created if missing)")
      ->required();
  command->add_flag("--no-ci", options->no_intervals, "Omit the 95% Wilson intervals");
  command->add_option("--label", options->label, "Only the cells of this policy label (a sweep cell's policy.json)");
  command->add_flag("--pool-labels", options->pool_labels,
                    "Pool the cells of different policy labels (refused otherwise)");
  command->footer(
      "Each summary.json needs task, robot, split, n_episodes and n_successful; camera (head or\n"
      "fixed, default head) and policy are optional. An episodes.jsonl beside it must hold those\n"
      "counts, and two files holding the same records (or one episode of one seed) are refused;\n"
      "a sweep's own summary.json (beside manifest.json) is not a cell; a cell without episodes is\n"
      "left out with a note. Cells sharing task, robot, split and camera\n"
      "(e.g. several seeds) are pooled; cells of different policy labels (policy.json next to the\n"
      "summary, else the policy's name) are refused unless --label picks one or --pool-labels. Rows: the suite's "
      "tasks, then the suite mean as the task\n"
      "average and pooled over episodes (with the Wilson interval of the pooled counts).");
  command->callback([options] { RunTable(*options); });
}

}  // namespace tavis::tools

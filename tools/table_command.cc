// `tavis table`: success-rate tables in the paper's layout from a folder of cell results.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>

#include "batch/results_table.h"
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
};

void WriteFile(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  out.close();
  if (!out) throw std::runtime_error(path + ": cannot write file");
}

void RunTable(const TableOptions& options) {
  const batch::ResultsTable table =
      batch::BuildResultsTable(batch::LoadCellResults(options.in_dir, configs::KnownRobots(DefaultConfigDir())), options.suite);
  const bool with_intervals = !options.no_intervals;
  // --out results/tables/acceptance: the folder part is made if it is missing.
  const std::filesystem::path folder = std::filesystem::path(options.out_prefix).parent_path();
  std::error_code error;
  if (!folder.empty() && !std::filesystem::create_directories(folder, error) && error) {
    throw std::runtime_error("--out " + options.out_prefix + ": cannot create the folder " + folder.string() + ": " +
                             error.message());
  }
  WriteFile(options.out_prefix + ".md", batch::FormatMarkdown(table, with_intervals));
  WriteFile(options.out_prefix + ".csv", batch::FormatCsv(table, with_intervals));
  std::cout << "wrote " << options.out_prefix << ".md and " << options.out_prefix << ".csv ("
            << table.tasks.size() << " tasks x " << table.columns.size() << " columns)\n";
}

}  // namespace

void RegisterTableCommand(CLI::App& app) {
  auto options = std::make_shared<TableOptions>();
  CLI::App* command = app.add_subcommand(
      "table", "Success-rate table (paper layout) from the summary.json files under a folder");
  command->add_option("--in", options->in_dir, "Folder searched recursively for summary.json")
      ->required();
  command->add_option("--suite", options->suite, "Suite whose tasks form the rows: " + scenarios::KnownSuites())
      ->required();
  command->add_option("--out", options->out_prefix, "Output prefix: writes PREFIX.md, PREFIX.csv (its folder is created if missing)")
      ->required();
  command->add_flag("--no-ci", options->no_intervals, "Omit the 95% Wilson intervals");
  command->footer(
      "Each summary.json needs task, robot, split, n_episodes and n_successful; camera (head or\n"
      "fixed, default head) and policy are optional. Cells sharing task, robot, split and camera\n"
      "(e.g. several seeds) are pooled. Rows: the suite's tasks, then the suite mean as the task\n"
      "average and pooled over episodes (with the Wilson interval of the pooled counts).");
  command->callback([options] { RunTable(*options); });
}

}  // namespace tavis::tools

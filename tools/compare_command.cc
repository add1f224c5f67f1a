// `tavis compare A B`: two results folders compared cell by cell (batch/report/cell_comparison.h),
// a Markdown table on stdout and a regression gate in the exit status.
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "batch/output/atomic_file.h"
#include "batch/output/output_folder.h"
#include "batch/report/cell_comparison.h"
#include "tools/commands.h"
#include "tools/exit_status.h"
#include "tools/option_parsing.h"

namespace tavis::tools {
namespace {

constexpr int kRegressionStatus = 1;
constexpr int kBadInputStatus = 2;

struct CompareOptions {
  std::string a;
  std::string b;
  double alpha = 0.05;
  std::string out;
  std::string label;    // both sides' cells of this policy label
  std::string label_a;  // A's (instead of --label)
  std::string label_b;  // B's (instead of --label)
};

// Refuses --out inside a compared folder: its compare.json beside the cells would be read as
// results by the next compare, table or verify of that folder.
void RequireOutOutside(const CompareOptions& options) {
  for (const std::string& side : {options.a, options.b}) {
    if (batch::output::IsSameOrInside(options.out, side))
      throw std::invalid_argument("--out " + options.out + " is inside " + side +
                                  ", a compared folder: compare writes nothing there; give a folder elsewhere");
  }
}

void RunCompare(const CompareOptions& options) {
  nlohmann::ordered_json json;
  std::string markdown;
  bool regression = false;
  // Everything is read and checked before anything is written: bad input leaves no file.
  try {
    if (!options.out.empty()) {
      batch::output::RequireUsableOutputPath(options.out);
      RequireOutOutside(options);
    }
    const std::vector<batch::report::CellCounts> a =
        batch::report::LoadComparedCells(options.a, options.label_a.empty() ? options.label : options.label_a);
    const std::vector<batch::report::CellCounts> b =
        batch::report::LoadComparedCells(options.b, options.label_b.empty() ? options.label : options.label_b);
    const batch::report::CellComparison comparison = batch::report::CompareCells(a, b, options.alpha);
    if (comparison.pairs.empty()) {
      throw std::runtime_error("no cell of " + options.a + " (" + std::to_string(a.size()) + ") pairs with a cell of " +
                               options.b + " (" + std::to_string(b.size()) +
                               "): cells pair by task, robot, split, camera, perturbations and seed");
    }
    json = batch::report::ComparisonJson(comparison, options.a, options.b);
    markdown = batch::report::ToMarkdown(batch::report::ComparisonTable(json)) + "\n" +
               json["verdict_line"].get<std::string>() + "\n";
    regression = comparison.regressions() > 0;
  } catch (const std::exception& error) {
    throw ExitStatus(kBadInputStatus, error.what());
  }
  if (!options.out.empty()) {
    const std::filesystem::path out(options.out);
    std::error_code error;
    if (!std::filesystem::create_directories(out, error) && error) {
      throw ExitStatus(kBadInputStatus, "--out " + options.out + ": cannot create the folder: " + error.message());
    }
    batch::output::WriteFileAtomically(out / "compare.md", markdown);
    batch::output::WriteFileAtomically(out / "compare.json", json.dump(2) + "\n");
  }
  std::cout << markdown;
  if (regression) throw ExitStatus(kRegressionStatus, "");
}

}  // namespace

void RegisterCompareCommand(CLI::App& app) {
  auto options = std::make_shared<CompareOptions>();
  CLI::App* command = app.add_subcommand(
      "compare", "Compare two results folders cell by cell (B against A); exit 1 when B is significantly worse");
  command->add_option("A", options->a, "The reference: one cell's folder or a folder of cells (a sweep's, eval cells)")
      ->required();
  command->add_option("B", options->b, "The candidate, compared against A: a cell's folder or a folder of cells")
      ->required();
  command
      ->add_option("--alpha", options->alpha,
                   "Significance level of McNemar's exact two-sided test: a cell where B has fewer B-only successes "
                   "than A-only ones at p < alpha is a regression")
      ->check(NumberIn(0.0, 1.0))
      ->capture_default_str();
  command->add_option("--out", options->out,
                      "Also write DIR/compare.md (the table) and DIR/compare.json (every number, the alpha and "
                      "each cell's verdict); the folder is created if missing");
  command->add_option("--label", options->label,
                      "Only the cells of this policy label on both sides (a sweep cell's policy.json, else the "
                      "policy's name): a folder holding several policies per cell");
  command->add_option("--label-a", options->label_a, "Only A's cells of this policy label (instead of --label)");
  command->add_option("--label-b", options->label_b,
                      "Only B's cells of this policy label (instead of --label; A and B may then be one folder)");
  command->footer(
      "Cells are paired by the identity their summary.json records: task, robot, split, camera,\n"
      "perturbations and seed (not the policy: comparing policies is the point); a cell on one side\n"
      "only is listed as unpaired. Episodes are paired by seed and episode index from each cell's\n"
      "episodes.jsonl (the same scene on both sides); where the sides ran different episodes, the\n"
      "test uses those both ran and says how many. Per pair: each side's successes with the 95%\n"
      "Wilson interval, B - A in points, the discordant episodes (A only : B only) and McNemar's p.\n"
      "The last line is the verdict. Exit status: 0 no regression, 1 a regression on some cell,\n"
      "2 bad input (a folder without cells, unreadable or invalid JSON, no cell paired, two policies'\n"
      "cells of one identity without --label, --out inside A or B; the error names the file, nothing\n"
      "is written).");
  // Usage errors are bad input too: 2, never the 1 of a regression.
  command->preparse_callback([](std::size_t) { SetUsageErrorStatus(kBadInputStatus); });
  command->callback([options] {
    if (!options->label.empty() && (!options->label_a.empty() || !options->label_b.empty()))
      throw ExitStatus(kBadInputStatus, "--label and --label-a/--label-b exclude each other");
    RunCompare(*options);
  });
}

}  // namespace tavis::tools

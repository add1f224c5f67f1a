// `tavis sweep`: the evaluation cells a spec names, run (or one shard of them) into one folder
// with a manifest, tables and an HTML report; `tavis sweep merge` combines the shards.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <unistd.h>

#include <tbb/info.h>

#include "batch/sweep/sweep_merge.h"
#include "batch/sweep/sweep_runner.h"
#include "batch/sweep/sweep_spec.h"
#include "configs/input_file.h"
#include "tools/commands.h"
#include "tools/error_text.h"
#include "tools/interrupt_notice.h"
#include "tools/option_parsing.h"

namespace tavis::tools {
namespace {

struct SweepOptions {
  std::string spec_file;
  std::string out;
  std::string shard = "0/1";
  std::string config_dir;
  int threads = 0;
  int concurrent_cells = 0;
  bool quiet = false;
  std::optional<int> videos;
};

struct MergeOptions {
  std::vector<std::string> shards;
  std::string out;
  std::string config_dir;
};

std::string ReadSpecText(const std::string& path) {
  const std::string not_a_file = configs::WhyNotARegularFile(path);
  if (!not_a_file.empty()) throw std::invalid_argument(path + ": the sweep spec " + not_a_file);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(path + ": cannot open the sweep spec");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// What an interrupted sweep in `out` kept (its cells' complete episodes) and the command that
// finishes it: the same one (Ctrl-C's line).
std::string InterruptedSweepLine(const std::filesystem::path& out) {
  namespace fs = std::filesystem;
  int64_t kept = 0;
  std::error_code error;
  fs::directory_iterator cell(out / "cells", error), end;
  for (; !error && cell != end; cell.increment(error)) kept += CompleteLines(cell->path() / "episodes.jsonl");
  return KeptLine(kept, out, "the sweep, run the same command", CommandLineWith({}, {}, ""));
}

void RunSweepCommand(const SweepOptions& options) {
  batch::sweep::SweepRunOptions run;
  run.spec_yaml = ReadSpecText(options.spec_file);
  run.config_dir = options.config_dir;
  const batch::sweep::SweepSpec spec =
      batch::sweep::ParseSweepSpec(run.spec_yaml, options.spec_file, options.config_dir);
  RunNamingFlags([&] {
    run.shard = batch::sweep::ParseShard(options.shard);
    batch::sweep::RequireShardHoldsCells(run.shard, batch::sweep::ExpandCells(spec, options.config_dir).size());
  });
  run.out_dir =
      options.out.empty() ? "results/" + std::filesystem::path(options.spec_file).stem().string() : options.out;
  run.threads = options.threads > 0 ? options.threads : tbb::info::default_concurrency();
  run.concurrent_cells = options.concurrent_cells;
  // A status line rewritten in place only makes sense on a terminal; a log gets the cell lines.
  run.quiet = options.quiet || isatty(STDERR_FILENO) == 0;
  run.videos = options.videos;
  SetInterruptNotice([out = std::filesystem::path(run.out_dir)] { return InterruptedSweepLine(out); });
  batch::sweep::RunSweep(spec, run);
  std::cout << (run.shard.count == 1 ? "sweep complete: " : "shard " + options.shard + " complete: ") << run.out_dir
            << (run.shard.count == 1 ? " (summary.json, tables/, report.html)"
                                     : " (merge the shards with `tavis sweep merge`)")
            << "\n";
}

}  // namespace

void RegisterSweepCommand(CLI::App& app) {
  auto options = std::make_shared<SweepOptions>();
  CLI::App* sweep = app.add_subcommand(
      "sweep",
      "Run the evaluation cells a sweep spec names (configs/sweeps/*.yaml) into one folder: cells/<id>/\n"
      "(each as `tavis eval` writes it), manifest.json, summary.json, tables/ (Markdown, CSV, LaTeX) and\n"
      "report.html. Rerun the same command to finish an interrupted sweep: complete cells are skipped,\n"
      "interrupted ones continue after their complete episodes.\n"
      "Sequential paired testing (opt-in, the spec's `sequential: {alpha: 0.05, block: 10, pairs: [cameras,\n"
      "perturbations], policies: [[A, B]]}`): paired cells (head vs each other camera, the base scene vs each\n"
      "perturbation, label A vs label B; same task, robot, split and seed) run `block` episodes at a time and\n"
      "stop together once an anytime-valid test on their discordant pairs decides at `alpha` (a wrong\n"
      "decision has probability <= alpha, however often it looks), or at `episodes`; each such cell's\n"
      "sequential.json says where and why it stopped, tables/sequential_pairs the decisions and the episodes\n"
      "saved (docs/sweeps.md). Without `sequential:` every cell runs all its episodes, as before.");
  sweep->add_option("spec", options->spec_file, "The sweep spec (YAML)");
  sweep->add_option("--out", options->out, "Output folder (default results/<spec name>)");
  sweep->add_option("--threads", options->threads, "Cores to use (0 = all; results do not depend on it)")
      ->check(IntegerIn(0, 1024))
      ->capture_default_str();
  sweep
      ->add_option("--concurrent-cells", options->concurrent_cells,
                   "Cells run at once, sharing the cores (0 = when every cell runs a built-in policy, one per 4\n"
                   "threads, at least one; otherwise as many as --threads; 1 runs them one after the other; results\n"
                   "do not depend on it)")
      ->check(IntegerIn(0, 1024))
      ->capture_default_str();
  sweep
      ->add_option("--shard", options->shard,
                   "Run shard I of N (0 <= I < N): the cells whose position in the spec's order is I mod N; the\n"
                   "shards' folders are then combined by `tavis sweep merge` (e.g. one Slurm array task each)")
      ->capture_default_str();
  sweep
      ->add_option(
          "--videos", options->videos,
          "Film each cell's first N episodes into cells/<id>/videos/episode_<i>.mp4, as `tavis eval --videos`\n"
          "does (in place of the spec's `videos:`; the records do not change)")
      ->check(IntegerIn(0, 100000000));
  sweep->add_flag(
      "--quiet", options->quiet,
      "No status line: one line per finished cell with the counts (the default when stderr is not a terminal)");
  AddConfigDirOption(*sweep, options->config_dir);

  auto merge_options = std::make_shared<MergeOptions>();
  CLI::App* merge = sweep->add_subcommand(
      "merge",
      "Combine the output folders of every shard of one sweep into OUT, with the whole sweep's results;\n"
      "refuses shards of different specs or program versions, and missing or incomplete shards");
  merge->add_option("shards", merge_options->shards, "The shards' output folders")->required();
  merge->add_option("--out", merge_options->out, "The merged output folder (new or empty)")->required();
  AddConfigDirOption(*merge, merge_options->config_dir);
  merge->callback([merge_options] {
    batch::sweep::MergeSweeps(merge_options->shards, merge_options->out, merge_options->config_dir);
    const std::size_t shards = merge_options->shards.size();
    std::cout << "merged " << shards << (shards == 1 ? " shard" : " shards") << " into " << merge_options->out
              << " (summary.json, tables/, report.html)\n";
  });

  sweep->callback([options, sweep, merge] {
    if (merge->parsed()) return;
    if (options->spec_file.empty())
      throw std::invalid_argument("sweep needs a spec file: tavis sweep SPEC.yaml --out DIR");
    if (sweep->count("--out") > 0 && options->out.empty())
      throw std::invalid_argument("--out must name a folder, got an empty string");
    RunSweepCommand(*options);
  });
}

}  // namespace tavis::tools

// Two results folders compared cell by cell (`tavis compare A B`): the cells of A and B are paired by
// what fixes their episodes' scenes (task, robot, split, camera protocol, perturbation levels,
// seed; not the policy: two policies are what is compared), and each pair's episodes by (seed,
// episode index), so episode i is the same scene on both sides. Per pair: each side's counts with
// the 95% Wilson interval, the difference B - A, and McNemar's exact two-sided test on the shared
// episodes; B is a regression where it does significantly worse (fewer B-only than A-only
// successes and p < alpha). compare.json is ComparisonJson's object, compare.md its table.
#pragma once

#include <filesystem>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/report/paired_statistics.h"
#include "batch/report/results_table.h"
#include "batch/report/sweep_tables.h"

namespace tavis::batch::report {

// What a cell is paired by.
struct CellIdentity {
  std::string task;
  std::string robot;
  std::string split;
  std::string camera;
  std::vector<std::string> perturbations;  // sorted "axis:level"; none for the base scene
  std::string seed;                        // summary.json's seed as text, empty when absent

  auto tied() const { return std::tie(task, robot, split, camera, perturbations, seed); }
  bool operator<(const CellIdentity& other) const { return tied() < other.tied(); }
  bool operator==(const CellIdentity& other) const { return tied() == other.tied(); }
  // "clutter-pick-lift gr1t2 id head lighting:dim s0"
  std::string label() const;
};

CellIdentity IdentityOf(const CellCounts& cell);

// The cells of one side: every summary.json under `folder` (itself a cell, or a folder of cells at
// any depth), read by ReadCellResult with its episodes.jsonl, each labelled by PolicyLabelOf; with
// a `label`, only the cells of that label (a sweep holding several policies). Throws
// std::runtime_error naming the file and the problem: a folder without any cell, unreadable or
// invalid JSON, a cell without episodes.jsonl or whose records do not all name their seed and
// episode, no cell of `label` (naming the labels there), two cells of one identity (naming their
// labels when they differ, which a `label` tells apart).
std::vector<CellCounts> LoadComparedCells(const std::filesystem::path& folder, const std::string& label = "");

// Episodes of `a` and `b` paired by (seed, episode index): only the episodes both recorded count.
PairedCounts PairEpisodes(const CellCounts& a, const CellCounts& b);

// What B's cell does against A's at `alpha`.
enum class CellVerdict { kNotSignificant, kRegression, kImprovement };
const char* ToString(CellVerdict verdict);
CellVerdict VerdictOf(const PairedCounts& counts, double alpha);

struct CellPair {
  CellIdentity identity;
  CellCounts a;
  CellCounts b;
  PairedCounts shared;  // over the shared episodes: first = A, second = B
  double mcnemar_p = 1.0;
  CellVerdict verdict = CellVerdict::kNotSignificant;
};

struct CellComparison {
  double alpha = 0.05;
  std::vector<CellPair> pairs;  // in identity order
  std::vector<CellCounts> only_a;
  std::vector<CellCounts> only_b;

  int regressions() const;
};

// Pairs the cells of the two sides by identity. Each side must hold at most one cell of an
// identity (LoadComparedCells checks it).
CellComparison CompareCells(const std::vector<CellCounts>& a, const std::vector<CellCounts>& b, double alpha);

// Every number: {"a", "b" (the folders), "alpha", "n_paired", "n_regressions", "verdict"
// ("regression" or "no regression"), "verdict_line", "pairs" (per pair its identity, each side's
// source, policy, n_episodes, n_successful, success_rate, ci_low, ci_high; difference_points (B -
// A, null when a side has no episode), shared_episodes, both, a_only, b_only, neither, mcnemar_p,
// verdict), "unpaired" (each cell of one side only: side, identity, source)}.
nlohmann::ordered_json ComparisonJson(const CellComparison& comparison, const std::string& a_folder,
                                      const std::string& b_folder);

// The table of ComparisonJson's pairs, its note naming the unpaired cells and the pairs whose
// episode sets differ.
TextTable ComparisonTable(const nlohmann::ordered_json& comparison);

// "no regression at alpha 0.05 over 3 paired cells", or "regression on 1 of 3 cells at alpha 0.05:
// CELL (A 100.0% -> B 0.0%, 16:0, p 3.05e-05)".
std::string VerdictLine(const CellComparison& comparison);

}  // namespace tavis::batch::report

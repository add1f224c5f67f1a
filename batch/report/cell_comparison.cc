#include "batch/report/cell_comparison.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <stdexcept>
#include <utility>

#include "batch/cell/statistics.h"
#include "batch/report/policy_label.h"

namespace tavis::batch::report {
namespace {

using Json = nlohmann::ordered_json;

std::string Alpha(double alpha) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g", alpha);
  return text;
}

std::string Plural(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

Json IdentityJson(const CellIdentity& identity) {
  Json seed = nullptr;
  if (!identity.seed.empty()) seed = Json::parse(identity.seed);
  return {{"cell", identity.label()},
          {"task", identity.task},
          {"robot", identity.robot},
          {"split", identity.split},
          {"camera", identity.camera},
          {"perturbations", identity.perturbations},
          {"seed", seed}};
}

Json SideJson(const CellCounts& cell) {
  const cell::ProportionInterval interval = cell::WilsonInterval(cell.n_successful, cell.n_episodes);
  Json rate = nullptr;
  if (cell.n_episodes > 0) rate = static_cast<double>(cell.n_successful) / static_cast<double>(cell.n_episodes);
  return {{"source", cell.source},         {"policy", cell.policy},
          {"n_episodes", cell.n_episodes}, {"n_successful", cell.n_successful},
          {"success_rate", rate},          {"ci_low", interval.low},
          {"ci_high", interval.high}};
}

// "16/16 100.0 [80.6, 100.0]"
std::string SideText(const Json& side) {
  const std::string counts =
      std::to_string(side["n_successful"].get<int64_t>()) + "/" + std::to_string(side["n_episodes"].get<int64_t>());
  if (side["success_rate"].is_null()) return counts;
  return counts + " " + Percent(side["success_rate"]) + " " + PercentInterval(side["ci_low"], side["ci_high"]);
}

// The cell's records by (seed, episode): its success.
std::map<std::pair<uint64_t, int64_t>, bool> Outcomes(const CellCounts& cell) {
  std::map<std::pair<uint64_t, int64_t>, bool> outcomes;
  for (std::size_t i = 0; i < cell.record_keys.size(); ++i)
    outcomes.emplace(cell.record_keys[i], cell.record_successes[i]);
  return outcomes;
}

}  // namespace

std::string CellIdentity::label() const {
  std::string text = task + " " + robot + " " + split + " " + camera;
  for (const std::string& level : perturbations) text += " " + level;
  return text + (seed.empty() ? "" : " s" + seed);
}

CellIdentity IdentityOf(const CellCounts& cell) {
  return {cell.task, cell.robot, cell.split, cell.camera, cell.perturbations, cell.seed};
}

std::vector<CellCounts> LoadComparedCells(const std::filesystem::path& folder, const std::string& label) {
  const std::vector<std::filesystem::path> paths = FindCellSummaries(folder);
  if (paths.empty()) {
    throw std::runtime_error(folder.string() + ": holds no cell (no summary.json at any depth, as `tavis eval` and " +
                             "`tavis sweep` write them)");
  }
  std::vector<CellCounts> cells;
  std::map<CellIdentity, const CellCounts*> earlier_of;
  std::map<std::string, int> labels;  // every label there, with its cells
  for (const std::filesystem::path& path : paths) {
    CellCounts cell = ReadCellResult(path);
    cell.label = PolicyLabelOf(cell);
    ++labels[cell.label];
    if (!label.empty() && cell.label != label) continue;
    if (!cell.has_records) {
      throw std::runtime_error(path.string() + ": no episodes.jsonl beside it: compare pairs the cells' episodes");
    }
    if (static_cast<int64_t>(cell.record_keys.size()) != cell.n_episodes) {
      throw std::runtime_error((path.parent_path() / "episodes.jsonl").string() + ": " +
                               std::to_string(cell.n_episodes - static_cast<int64_t>(cell.record_keys.size())) +
                               " records do not name their \"seed\" and \"episode\": they cannot be paired");
    }
    cells.push_back(std::move(cell));
  }
  std::string label_list;
  for (const auto& [name, n] : labels)
    label_list +=
        (label_list.empty() ? "" : ", ") + name + " (" + Plural(static_cast<std::size_t>(n), "cell", "cells") + ")";
  if (cells.empty())
    throw std::runtime_error(folder.string() + ": no cell has label " + label + " (labels: " + label_list + ")");
  for (const CellCounts& cell : cells) {
    const auto [earlier, inserted] = earlier_of.emplace(IdentityOf(cell), &cell);
    if (inserted) continue;
    const bool two_labels = earlier->second->label != cell.label;
    throw std::runtime_error(folder.string() + " holds two cells of " + IdentityOf(cell).label() + ": " +
                             earlier->second->source + " and " + cell.source +
                             (two_labels ? " (policy labels " + earlier->second->label + " and " + cell.label +
                                               ": choose one with --label, labels there: " + label_list + ")"
                                         : " (compare one policy's cells per folder)"));
  }
  return cells;
}

PairedCounts PairEpisodes(const CellCounts& a, const CellCounts& b) {
  const std::map<std::pair<uint64_t, int64_t>, bool> b_outcomes = Outcomes(b);
  PairedCounts counts;
  for (const auto& [key, a_success] : Outcomes(a)) {
    const auto it = b_outcomes.find(key);
    if (it == b_outcomes.end()) continue;
    const bool b_success = it->second;
    ++(a_success && b_success ? counts.both
       : a_success            ? counts.first_only
       : b_success            ? counts.second_only
                              : counts.neither);
  }
  return counts;
}

const char* ToString(CellVerdict verdict) {
  switch (verdict) {
    case CellVerdict::kRegression: return "regression";
    case CellVerdict::kImprovement: return "improvement";
    case CellVerdict::kNotSignificant: break;
  }
  return "not significant";
}

CellVerdict VerdictOf(const PairedCounts& counts, double alpha) {
  if (McNemarExactP(counts.first_only, counts.second_only) >= alpha) return CellVerdict::kNotSignificant;
  if (counts.second_only < counts.first_only) return CellVerdict::kRegression;
  if (counts.second_only > counts.first_only) return CellVerdict::kImprovement;
  return CellVerdict::kNotSignificant;
}

int CellComparison::regressions() const {
  return static_cast<int>(std::count_if(pairs.begin(), pairs.end(),
                                        [](const CellPair& pair) { return pair.verdict == CellVerdict::kRegression; }));
}

CellComparison CompareCells(const std::vector<CellCounts>& a, const std::vector<CellCounts>& b, double alpha) {
  CellComparison comparison;
  comparison.alpha = alpha;
  std::map<CellIdentity, const CellCounts*> b_cells;
  for (const CellCounts& cell : b) b_cells.emplace(IdentityOf(cell), &cell);
  std::map<CellIdentity, const CellCounts*> a_cells;
  for (const CellCounts& cell : a) {
    a_cells.emplace(IdentityOf(cell), &cell);
    const auto match = b_cells.find(IdentityOf(cell));
    if (match == b_cells.end()) {
      comparison.only_a.push_back(cell);
      continue;
    }
    CellPair pair{IdentityOf(cell), cell, *match->second, PairEpisodes(cell, *match->second)};
    pair.mcnemar_p = McNemarExactP(pair.shared.first_only, pair.shared.second_only);
    pair.verdict = VerdictOf(pair.shared, alpha);
    comparison.pairs.push_back(std::move(pair));
  }
  for (const CellCounts& cell : b) {
    if (a_cells.count(IdentityOf(cell)) == 0) comparison.only_b.push_back(cell);
  }
  std::sort(comparison.pairs.begin(), comparison.pairs.end(),
            [](const CellPair& x, const CellPair& y) { return x.identity < y.identity; });
  return comparison;
}

Json ComparisonJson(const CellComparison& comparison, const std::string& a_folder, const std::string& b_folder) {
  Json pairs = Json::array();
  for (const CellPair& pair : comparison.pairs) {
    Json row = IdentityJson(pair.identity);
    row["a"] = SideJson(pair.a);
    row["b"] = SideJson(pair.b);
    row["difference_points"] = nullptr;
    if (!row["a"]["success_rate"].is_null() && !row["b"]["success_rate"].is_null()) {
      row["difference_points"] =
          100.0 * (row["b"]["success_rate"].get<double>() - row["a"]["success_rate"].get<double>());
    }
    row["shared_episodes"] = pair.shared.pairs();
    row["both"] = pair.shared.both;
    row["a_only"] = pair.shared.first_only;
    row["b_only"] = pair.shared.second_only;
    row["neither"] = pair.shared.neither;
    row["mcnemar_p"] = pair.mcnemar_p;
    row["verdict"] = ToString(pair.verdict);
    pairs.push_back(std::move(row));
  }
  Json unpaired = Json::array();
  for (const auto& [side, cells] : {std::make_pair("a", &comparison.only_a), std::make_pair("b", &comparison.only_b)}) {
    for (const CellCounts& cell : *cells) {
      Json row = {{"side", side}};
      row.update(IdentityJson(IdentityOf(cell)));
      row["source"] = cell.source;
      unpaired.push_back(std::move(row));
    }
  }
  return {{"a", a_folder},
          {"b", b_folder},
          {"alpha", comparison.alpha},
          {"n_paired", comparison.pairs.size()},
          {"n_regressions", comparison.regressions()},
          {"verdict", comparison.regressions() > 0 ? "regression" : "no regression"},
          {"verdict_line", VerdictLine(comparison)},
          {"pairs", std::move(pairs)},
          {"unpaired", std::move(unpaired)}};
}

TextTable ComparisonTable(const Json& comparison) {
  TextTable table{"compare",
                  "B = " + comparison["b"].get<std::string>() + " against A = " + comparison["a"].get<std::string>() +
                      " (alpha " + Alpha(comparison["alpha"]) + ")",
                  {"cell", "A", "B", "B - A (points)", "shared", "A only : B only", "McNemar p", "verdict"},
                  {},
                  ""};
  std::string note =
      "A and B: successful/episodes, success % and its 95% Wilson interval. McNemar's exact two-sided test on "
      "the episodes both sides ran (same seed and episode index, so the same scene).";
  for (const Json& row : comparison["pairs"]) {
    const Json& difference = row["difference_points"];
    table.rows.push_back(
        {row["cell"], SideText(row["a"]), SideText(row["b"]),
         difference.is_null() ? "-" : Points(difference.get<double>() / 100.0),
         std::to_string(row["shared_episodes"].get<int64_t>()),
         std::to_string(row["a_only"].get<int64_t>()) + " : " + std::to_string(row["b_only"].get<int64_t>()),
         PValue(row["mcnemar_p"]), row["verdict"]});
    const int64_t shared = row["shared_episodes"], a_n = row["a"]["n_episodes"], b_n = row["b"]["n_episodes"];
    if (shared != a_n || shared != b_n) {
      note += "\n" + row["cell"].get<std::string>() + ": A and B share " + std::to_string(shared) +
              " episodes (A ran " + std::to_string(a_n) + ", B " + std::to_string(b_n) +
              "): McNemar's test is on those.";
    }
  }
  for (const Json& row : comparison["unpaired"]) {
    note += "\nunpaired: " + row["cell"].get<std::string>() + " only in " +
            (row["side"] == "a" ? std::string("A") : std::string("B")) + " (" + row["source"].get<std::string>() + ")";
  }
  table.note = note;
  return table;
}

std::string VerdictLine(const CellComparison& comparison) {
  const std::string alpha = Alpha(comparison.alpha);
  const int regressions = comparison.regressions();
  if (regressions == 0) {
    return "no regression at alpha " + alpha + " over " +
           Plural(comparison.pairs.size(), "paired cell", "paired cells");
  }
  std::string line = "regression on " + std::to_string(regressions) + " of " +
                     Plural(comparison.pairs.size(), "cell", "cells") + " at alpha " + alpha + ":";
  std::string separator = " ";
  for (const CellPair& pair : comparison.pairs) {
    if (pair.verdict != CellVerdict::kRegression) continue;
    const auto rate = [](const CellCounts& cell) {
      return Percent(static_cast<double>(cell.n_successful) / static_cast<double>(cell.n_episodes)) + "%";
    };
    line += separator + pair.identity.label() + " (A " + rate(pair.a) + " -> B " + rate(pair.b) + ", " +
            std::to_string(pair.shared.first_only) + ":" + std::to_string(pair.shared.second_only) + ", p " +
            PValue(pair.mcnemar_p) + ")";
    separator = "; ";
  }
  return line;
}

}  // namespace tavis::batch::report

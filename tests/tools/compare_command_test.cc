// `tavis compare A B` on folders of cells that `tavis eval` and `tavis sweep` wrote: a folder
// against its copy is no regression and shows each side's summary, a failing policy against the
// expert is one (exit 1), two sweeps pair cell by cell, bad input exits 2 naming the file and
// writes nothing.
#include <cstdio>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "tool_runner.h"

namespace tavis::tools {
namespace {

class CompareCommand : public TavisCommandTest {
 protected:
  // One cell of clutter-pick-lift (the quickest task) into `dir`.
  void Eval(const fs::path& dir, const std::string& policy, int episodes, int seed) const {
    const RunResult run =
        Run("eval --task clutter-pick-lift --policy " + policy + " --episodes " + std::to_string(episodes) +
            " --seed " + std::to_string(seed) + " --threads 2 --out " + Quote(dir.string()));
    ASSERT_EQ(run.exit_code, 0) << run.err;
  }

  // A two-cell `tavis sweep` of clutter-pick-lift (head and fixed camera) with `policy` into `dir`.
  void Sweep(const fs::path& dir, const std::string& policy) const {
    const fs::path spec = root_ / (policy + ".yaml");
    std::ofstream(spec) << "tasks: [clutter-pick-lift]\nrobots: [gr1t2]\nsplits: [id]\ncameras: [head, fixed]\n"
                           "seeds: [0]\nepisodes: 12\npolicy:\n  name: "
                        << policy << "\n";
    const RunResult run = Run("sweep " + Quote(spec.string()) + " --threads 2 --quiet --out " + Quote(dir.string()));
    ASSERT_EQ(run.exit_code, 0) << run.err;
  }

  RunResult Compare(const fs::path& a, const fs::path& b, const std::string& more = "") const {
    return Run("compare " + Quote(a.string()) + " " + Quote(b.string()) + more);
  }

  static nlohmann::json ReadJson(const fs::path& path) { return nlohmann::json::parse(ReadText(path)); }
};

std::string Percent(double fraction) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f", 100.0 * fraction);
  return text;
}

std::string LastLine(const std::string& text) { return Lines(text).empty() ? "" : Lines(text).back(); }

TEST_F(CompareCommand, AFolderAgainstItsCopyIsNoRegressionWithEachSidesSummary) {
  Eval(root_ / "main" / "s0", "expert", 6, 0);
  Eval(root_ / "main" / "nested" / "s1", "expert", 3, 1);
  fs::copy(root_ / "main", root_ / "copy", fs::copy_options::recursive);
  const RunResult run = Compare(root_ / "main", root_ / "copy", " --out " + Quote((root_ / "report").string()));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_EQ(LastLine(run.out), "no regression at alpha 0.05 over 2 paired cells") << run.out;
  EXPECT_EQ(ReadText(root_ / "report" / "compare.md"), run.out);
  const nlohmann::json json = ReadJson(root_ / "report" / "compare.json");
  EXPECT_EQ(json["alpha"], 0.05);
  EXPECT_EQ(json["verdict"], "no regression");
  ASSERT_EQ(json["pairs"].size(), 2u);
  for (const auto& [pair, dir] :
       {std::make_pair(json["pairs"][0], "s0"), std::make_pair(json["pairs"][1], "nested/s1")}) {
    const nlohmann::json summary = ReadJson(root_ / "main" / dir / "summary.json");
    for (const char* side : {"a", "b"}) {
      EXPECT_EQ(pair[side]["n_episodes"], summary["n_episodes"]);
      EXPECT_EQ(pair[side]["n_successful"], summary["n_successful"]);
      EXPECT_EQ(pair[side]["ci_low"].get<double>(), summary["ci_low"].get<double>());
      EXPECT_EQ(pair[side]["ci_high"].get<double>(), summary["ci_high"].get<double>());
    }
    EXPECT_EQ(pair["shared_episodes"], summary["n_episodes"]);
    EXPECT_EQ(pair["mcnemar_p"], 1.0);
    EXPECT_EQ(pair["verdict"], "not significant");
    // The table's row: both sides as the summary has them, no difference, no discordant episode.
    const std::string side = std::to_string(summary["n_successful"].get<int>()) + "/" +
                             std::to_string(summary["n_episodes"].get<int>()) + " " + Percent(summary["success_rate"]) +
                             " [" + Percent(summary["ci_low"]) + ", " + Percent(summary["ci_high"]) + "]";
    const std::string row = "| " + pair["cell"].get<std::string>() + " | " + side + " | " + side + " | +0.0 | " +
                            std::to_string(summary["n_episodes"].get<int>()) + " | 0 : 0 | 1 | not significant |";
    EXPECT_NE(run.out.find(row), std::string::npos) << row << "\n" << run.out;
  }
}

TEST_F(CompareCommand, AFailingPolicyAgainstTheExpertIsARegressionAndTheReverseIsNot) {
  Eval(root_ / "main" / "s0", "expert", 16, 0);
  Eval(root_ / "change" / "s0", "hold", 16, 0);
  Eval(root_ / "change" / "s1", "hold", 2, 1);  // no expert cell of seed 1: unpaired
  const nlohmann::json expert = ReadJson(root_ / "main" / "s0" / "summary.json");
  ASSERT_GE(expert["n_successful"].get<int>(), 6) << "the expert must win enough episodes for p < 0.05";

  const RunResult worse = Compare(root_ / "main", root_ / "change", " --out " + Quote((root_ / "report").string()));
  EXPECT_EQ(worse.exit_code, 1) << worse.out << worse.err;
  EXPECT_EQ(
      LastLine(worse.out).rfind("regression on 1 of 1 cell at alpha 0.05: clutter-pick-lift gr1t2 id head s0 (A ", 0),
      0u)
      << worse.out;
  EXPECT_NE(worse.out.find("unpaired: clutter-pick-lift gr1t2 id head s1 only in B"), std::string::npos) << worse.out;
  const nlohmann::json json = ReadJson(root_ / "report" / "compare.json");
  EXPECT_EQ(json["verdict"], "regression");
  EXPECT_EQ(json["n_regressions"], 1);
  EXPECT_EQ(json["pairs"][0]["a_only"], expert["n_successful"]);
  EXPECT_EQ(json["pairs"][0]["b_only"], 0);
  EXPECT_LT(json["pairs"][0]["mcnemar_p"].get<double>(), 0.05);
  EXPECT_EQ(json["pairs"][0]["verdict"], "regression");
  EXPECT_EQ(json["unpaired"].size(), 1u);
  if (expert["n_successful"] == 16) {
    EXPECT_EQ(LastLine(worse.out),
              "regression on 1 of 1 cell at alpha 0.05: clutter-pick-lift gr1t2 id head s0 "
              "(A 100.0% -> B 0.0%, 16:0, p 3.05e-05)");
  }

  // One cell's folder against another's is the same comparison; the expert against hold is not worse.
  EXPECT_EQ(Compare(root_ / "main" / "s0", root_ / "change" / "s0").exit_code, 1);
  const RunResult better = Compare(root_ / "change", root_ / "main");
  EXPECT_EQ(better.exit_code, 0) << better.out << better.err;
  EXPECT_EQ(LastLine(better.out), "no regression at alpha 0.05 over 1 paired cell") << better.out;
  EXPECT_NE(better.out.find("| improvement |"), std::string::npos) << better.out;
  // Below the tiny p nothing is significant.
  EXPECT_EQ(Compare(root_ / "main", root_ / "change", " --alpha 1e-9").exit_code, 0);
}

// Two sweeps' folders (cells/<id>/ beside the sweep's own summary.json, manifest and tables) pair
// cell by cell: the sweep-level summary is not a cell.
TEST_F(CompareCommand, TwoSweepsPairCellByCell) {
  Sweep(root_ / "expert", "expert");
  Sweep(root_ / "hold", "hold");
  const RunResult worse = Compare(root_ / "expert", root_ / "hold");
  EXPECT_EQ(worse.exit_code, 1) << worse.out << worse.err;
  EXPECT_NE(worse.out.find("| clutter-pick-lift gr1t2 id head s0 |"), std::string::npos) << worse.out;
  EXPECT_NE(worse.out.find("| clutter-pick-lift gr1t2 id fixed s0 |"), std::string::npos) << worse.out;
  EXPECT_EQ(worse.out.find("unpaired"), std::string::npos) << worse.out;
  EXPECT_EQ(LastLine(worse.out).rfind("regression on 2 of 2 cells at alpha 0.05: ", 0), 0u) << worse.out;
  const RunResult same = Compare(root_ / "expert", root_ / "expert");
  EXPECT_EQ(same.exit_code, 0) << same.out << same.err;
  EXPECT_EQ(LastLine(same.out), "no regression at alpha 0.05 over 2 paired cells") << same.out;
}

// A sweep of two labelled policies holds two cells per identity: without --label compare refuses
// it naming both labels (exit 2); --label picks one on both sides, --label-a/--label-b compare the
// sweep's two policies against each other.
TEST_F(CompareCommand, LabelPicksOnePolicyOfASweepHoldingTwo) {
  const fs::path spec = root_ / "two.yaml";
  std::ofstream(spec) << "tasks: [clutter-pick-lift]\nrobots: [gr1t2]\nsplits: [id]\ncameras: [head]\n"
                         "seeds: [0]\nepisodes: 12\npolicies:\n  - {label: good, name: expert}\n"
                         "  - {label: bad, name: hold}\n";
  const fs::path sweep = root_ / "two";
  const RunResult run = Run("sweep " + Quote(spec.string()) + " --threads 2 --quiet --out " + Quote(sweep.string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;

  const RunResult mixed = Compare(sweep, sweep);
  EXPECT_EQ(mixed.exit_code, 2) << mixed.out << mixed.err;
  EXPECT_NE(mixed.err.find("policy labels "), std::string::npos) << mixed.err;
  EXPECT_NE(mixed.err.find("labels there: bad (1 cell), good (1 cell)"), std::string::npos) << mixed.err;

  const RunResult same = Compare(sweep, sweep, " --label good");
  EXPECT_EQ(same.exit_code, 0) << same.out << same.err;
  EXPECT_EQ(LastLine(same.out), "no regression at alpha 0.05 over 1 paired cell") << same.out;
  const RunResult worse = Compare(sweep, sweep, " --label-a good --label-b bad");
  EXPECT_EQ(worse.exit_code, 1) << worse.out << worse.err;
  EXPECT_EQ(LastLine(worse.out).rfind("regression on 1 of 1 cell at alpha 0.05: clutter-pick-lift gr1t2 id head s0", 0),
            0u)
      << worse.out;
  EXPECT_EQ(Compare(sweep, sweep, " --label-a bad --label-b good").exit_code, 0);

  const RunResult unknown = Compare(sweep, sweep, " --label nobody");
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find(sweep.string() + ": no cell has label nobody (labels: bad (1 cell), good (1 cell))"),
            std::string::npos)
      << unknown.err;
  EXPECT_EQ(Compare(sweep, sweep, " --label good --label-b bad").exit_code, 2);
}

// --out inside a compared folder would put compare.json among the cells it reads: refused with
// exit 2 before anything is written, as verify --json is.
TEST_F(CompareCommand, OutInsideAComparedFolderIsRefused) {
  Eval(root_ / "a", "expert", 2, 0);
  Eval(root_ / "b", "expert", 2, 0);
  for (const fs::path& out : {root_ / "a" / "report", root_ / "b", root_ / "b" / "deeper" / "report"}) {
    const RunResult run = Compare(root_ / "a", root_ / "b", " --out " + Quote(out.string()));
    EXPECT_EQ(run.exit_code, 2) << out;
    EXPECT_NE(run.err.find("--out " + out.string() + " is inside "), std::string::npos) << run.err;
    EXPECT_TRUE(run.out.empty()) << run.out;
  }
  EXPECT_FALSE(fs::exists(root_ / "a" / "report"));
  EXPECT_FALSE(fs::exists(root_ / "b" / "deeper"));
  EXPECT_FALSE(fs::exists(root_ / "b" / "compare.json"));
  EXPECT_EQ(Compare(root_ / "a", root_ / "b", " --out " + Quote((root_ / "report").string())).exit_code, 0);
}

TEST_F(CompareCommand, BadInputExitsTwoNamingTheFileAndWritesNothing) {
  fs::create_directories(root_ / "empty" / "inside");
  fs::create_directories(root_ / "broken" / "cell");
  std::ofstream(root_ / "broken" / "cell" / "summary.json") << "{\"task\": \"clutter-pick-lift\",";
  const std::string out = " --out " + Quote((root_ / "report").string());

  const RunResult empty = Compare(root_ / "empty", root_ / "broken", out);
  EXPECT_EQ(empty.exit_code, 2);
  EXPECT_NE(empty.err.find((root_ / "empty").string() + ": holds no cell"), std::string::npos) << empty.err;
  const RunResult broken = Compare(root_ / "broken", root_ / "broken", out);
  EXPECT_EQ(broken.exit_code, 2);
  EXPECT_NE(broken.err.find((root_ / "broken" / "cell" / "summary.json").string() + ": invalid JSON"),
            std::string::npos)
      << broken.err;
  const RunResult missing = Compare(root_ / "nowhere", root_ / "broken", out);
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find((root_ / "nowhere").string() + ": not a directory"), std::string::npos) << missing.err;
  EXPECT_TRUE(empty.out.empty() && broken.out.empty() && missing.out.empty());
  EXPECT_FALSE(fs::exists(root_ / "report"));
  // Usage errors are bad input as well, never the 1 of a regression.
  EXPECT_EQ(Run("compare " + Quote((root_ / "empty").string())).exit_code, 2);
  EXPECT_EQ(Compare(root_ / "empty", root_ / "empty", " --alpha 2").exit_code, 2);
  EXPECT_EQ(Run("compare --help").exit_code, 0);
}

}  // namespace
}  // namespace tavis::tools

// Two results folders compared cell by cell: cells paired by identity, episodes by (seed, episode),
// McNemar's exact test on a case worked by hand, and what a folder that cannot be compared says.
#include "batch/report/cell_comparison.h"
#include "tests/support/test_folder.h"
#include "tests/support/thrown_message.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "batch/cell/statistics.h"

namespace tavis::batch::report {
namespace {

// A cell of clutter-pick-lift gr1t2 id head: episodes first_episode, first_episode + 1, ... of
// `seed`, succeeding as `successes` says.
CellCounts Cell(const std::string& policy, const std::vector<bool>& successes, const std::string& seed = "0",
                int64_t first_episode = 0) {
  CellCounts cell;
  cell.task = "clutter-pick-lift";
  cell.robot = "gr1t2";
  cell.split = "id";
  cell.policy = policy;
  cell.seed = seed;
  cell.source = policy + "/s" + seed + "/summary.json";
  cell.has_records = true;
  for (std::size_t i = 0; i < successes.size(); ++i) {
    cell.record_keys.emplace_back(std::stoull(seed), first_episode + static_cast<int64_t>(i));
    cell.record_successes.push_back(successes[i]);
    cell.n_successful += successes[i] ? 1 : 0;
  }
  cell.n_episodes = static_cast<int64_t>(successes.size());
  return cell;
}

// Episodes 0-6 succeed under A only, 7 under B only, 8 under both, 9 under neither.
std::vector<bool> ASide() { return {true, true, true, true, true, true, true, false, true, false}; }
std::vector<bool> BSide() { return {false, false, false, false, false, false, false, true, true, false}; }

TEST(CellComparison, McNemarOnTheDiscordantEpisodesWorkedByHand) {
  const PairedCounts counts = PairEpisodes(Cell("expert", ASide()), Cell("hold", BSide()));
  EXPECT_EQ(counts.both, 1);
  EXPECT_EQ(counts.first_only, 7);
  EXPECT_EQ(counts.second_only, 1);
  EXPECT_EQ(counts.neither, 1);
  // 7 : 1, n = 8: P[X <= 1] = (C(8,0) + C(8,1)) / 2^8 = 9/256, two-sided p = 2 * 9/256.
  const CellComparison comparison = CompareCells({Cell("expert", ASide())}, {Cell("hold", BSide())}, 0.05);
  ASSERT_EQ(comparison.pairs.size(), 1u);
  EXPECT_NEAR(comparison.pairs[0].mcnemar_p, 0.0703125, 1e-12);
  EXPECT_EQ(comparison.pairs[0].verdict, CellVerdict::kNotSignificant);
  EXPECT_EQ(comparison.regressions(), 0);
  EXPECT_EQ(VerdictLine(comparison), "no regression at alpha 0.05 over 1 paired cell");
  // At alpha 0.1 B's fewer successes are a regression; A and B swapped, an improvement.
  const CellComparison at_ten = CompareCells({Cell("expert", ASide())}, {Cell("hold", BSide())}, 0.1);
  EXPECT_EQ(at_ten.pairs[0].verdict, CellVerdict::kRegression);
  EXPECT_EQ(VerdictLine(at_ten),
            "regression on 1 of 1 cell at alpha 0.1: clutter-pick-lift gr1t2 id head s0 (A 80.0% -> B 20.0%, 7:1, "
            "p 0.0703)");
  EXPECT_EQ(CompareCells({Cell("hold", BSide())}, {Cell("expert", ASide())}, 0.1).pairs[0].verdict,
            CellVerdict::kImprovement);
}

TEST(CellComparison, JsonHoldsEveryNumberOfAPair) {
  const CellComparison comparison = CompareCells({Cell("expert", ASide())}, {Cell("hold", BSide())}, 0.1);
  const nlohmann::ordered_json json = ComparisonJson(comparison, "main", "change");
  EXPECT_EQ(json["alpha"], 0.1);
  EXPECT_EQ(json["n_paired"], 1);
  EXPECT_EQ(json["n_regressions"], 1);
  EXPECT_EQ(json["verdict"], "regression");
  const nlohmann::ordered_json& pair = json["pairs"][0];
  EXPECT_EQ(pair["cell"], "clutter-pick-lift gr1t2 id head s0");
  EXPECT_EQ(pair["seed"], 0);
  EXPECT_EQ(pair["a"]["policy"], "expert");
  EXPECT_EQ(pair["a"]["n_successful"], 8);
  EXPECT_EQ(pair["b"]["n_episodes"], 10);
  EXPECT_DOUBLE_EQ(pair["b"]["ci_low"].get<double>(), cell::WilsonInterval(2, 10).low);
  EXPECT_DOUBLE_EQ(pair["difference_points"].get<double>(), -60.0);
  EXPECT_EQ(pair["shared_episodes"], 10);
  EXPECT_EQ(pair["a_only"], 7);
  EXPECT_EQ(pair["b_only"], 1);
  EXPECT_EQ(pair["verdict"], "regression");
  const TextTable table = ComparisonTable(json);
  ASSERT_EQ(table.rows.size(), 1u);
  EXPECT_EQ(table.rows[0][1], "8/10 80.0 [49.0, 94.3]");
  EXPECT_EQ(table.rows[0][3], "-60.0");
  EXPECT_EQ(table.rows[0][5], "7 : 1");
}

TEST(CellComparison, PairsCellsByIdentityNotByPolicyOrOrder) {
  CellCounts a_perturbed = Cell("expert", {true, true});
  a_perturbed.perturbations = {"camera:tilt-15", "lighting:dim"};
  CellCounts b_perturbed = Cell("hold", {false, true});
  b_perturbed.perturbations = {"camera:tilt-15", "lighting:dim"};
  CellCounts b_fixed = Cell("hold", {true, true});
  b_fixed.camera = "fixed";
  const CellComparison comparison =
      CompareCells({Cell("expert", {true, false}, "1"), a_perturbed, Cell("expert", {true, true}, "0")},
                   {b_fixed, b_perturbed, Cell("hold", {false, false}, "1"), Cell("hold", {true, false}, "0")}, 0.05);
  ASSERT_EQ(comparison.pairs.size(), 3u);
  // In identity order: the base scene's seeds 0 and 1, then seed 0 under the levels.
  EXPECT_EQ(comparison.pairs[0].identity.label(), "clutter-pick-lift gr1t2 id head s0");
  EXPECT_EQ(comparison.pairs[0].b.n_successful, 1);
  EXPECT_EQ(comparison.pairs[1].identity.seed, "1");
  EXPECT_EQ(comparison.pairs[1].shared.first_only, 1);
  EXPECT_EQ(comparison.pairs[2].identity.label(), "clutter-pick-lift gr1t2 id head camera:tilt-15 lighting:dim s0");
  EXPECT_EQ(comparison.pairs[2].a.n_successful, 2);
  EXPECT_EQ(comparison.pairs[2].shared.first_only, 1);
  EXPECT_TRUE(comparison.only_a.empty());
  ASSERT_EQ(comparison.only_b.size(), 1u);
  EXPECT_EQ(comparison.only_b[0].camera, "fixed");
}

TEST(CellComparison, ListsTheCellsOfOneSideAsUnpaired) {
  CellCounts ood = Cell("hold", {false});
  ood.split = "ood-spatial";
  const CellComparison comparison =
      CompareCells({Cell("expert", {true}), Cell("expert", {true}, "2")}, {Cell("hold", {false}), ood}, 0.05);
  ASSERT_EQ(comparison.pairs.size(), 1u);
  ASSERT_EQ(comparison.only_a.size(), 1u);
  EXPECT_EQ(comparison.only_a[0].seed, "2");
  ASSERT_EQ(comparison.only_b.size(), 1u);
  const nlohmann::ordered_json json = ComparisonJson(comparison, "main", "change");
  ASSERT_EQ(json["unpaired"].size(), 2u);
  EXPECT_EQ(json["unpaired"][0]["side"], "a");
  EXPECT_EQ(json["unpaired"][0]["cell"], "clutter-pick-lift gr1t2 id head s2");
  EXPECT_EQ(json["unpaired"][1]["side"], "b");
  EXPECT_EQ(json["unpaired"][1]["split"], "ood-spatial");
  const std::string note = ComparisonTable(json).note;
  EXPECT_NE(note.find("unpaired: clutter-pick-lift gr1t2 id head s2 only in A (expert/s2/summary.json)"),
            std::string::npos)
      << note;
  EXPECT_NE(note.find("unpaired: clutter-pick-lift gr1t2 ood-spatial head s0 only in B"), std::string::npos) << note;
}

TEST(CellComparison, TestsTheEpisodesBothSidesRanAndSaysHowMany) {
  // A ran episodes 0-9 (all successful), B 4-11 (all failed): they share 4-9.
  const CellComparison comparison = CompareCells({Cell("expert", std::vector<bool>(10, true))},
                                                 {Cell("hold", std::vector<bool>(8, false), "0", 4)}, 0.05);
  ASSERT_EQ(comparison.pairs.size(), 1u);
  EXPECT_EQ(comparison.pairs[0].shared.pairs(), 6);
  EXPECT_EQ(comparison.pairs[0].shared.first_only, 6);
  EXPECT_NEAR(comparison.pairs[0].mcnemar_p, 2.0 / 64.0, 1e-12);
  EXPECT_EQ(comparison.pairs[0].verdict, CellVerdict::kRegression);
  const nlohmann::ordered_json json = ComparisonJson(comparison, "main", "change");
  EXPECT_EQ(json["pairs"][0]["shared_episodes"], 6);
  EXPECT_EQ(json["pairs"][0]["a"]["n_episodes"], 10);
  const std::string note = ComparisonTable(json).note;
  EXPECT_NE(note.find("clutter-pick-lift gr1t2 id head s0: A and B share 6 episodes (A ran 10, B 8)"),
            std::string::npos)
      << note;
}

class ComparedCellsTest : public testing::TestFolder {
 protected:
  // A cell as `tavis eval` writes it: summary.json and one record per episode.
  void WriteCell(const std::string& dir, const std::string& extra, const std::vector<bool>& successes) {
    std::ostringstream records;
    int successful = 0;
    for (std::size_t i = 0; i < successes.size(); ++i) {
      records << R"({"episode": )" << i << R"(, "seed": 0, "success": )" << (successes[i] ? "true" : "false") << "}\n";
      successful += successes[i] ? 1 : 0;
    }
    testing::WriteTextFile(root_ / dir / "episodes.jsonl", records.str());
    testing::WriteTextFile(root_ / dir / "summary.json",
                           R"({"task": "clutter-pick-lift", "robot": "gr1t2", "split": "id", "camera": "head", )"
                           R"("policy": "expert", "seed": 0, )" +
                               extra + R"("n_episodes": )" + std::to_string(successes.size()) +
                               R"(, "n_successful": )" + std::to_string(successful) + "}");
  }

  std::string LoadError(const std::string& dir) {
    return testing::ThrownMessage<std::runtime_error>([&] { LoadComparedCells(root_ / dir); });
  }
};

TEST_F(ComparedCellsTest, ReadsACellFolderOrAFolderOfCellsAtAnyDepth) {
  WriteCell("sweep/cells/a/b/base", "", {true, false});
  WriteCell("sweep/cells/dim", R"("perturbations": ["lighting:dim", "camera:tilt-15"], )", {true});
  const std::vector<CellCounts> cells = LoadComparedCells(root_ / "sweep");
  ASSERT_EQ(cells.size(), 2u);
  EXPECT_EQ(cells[0].record_successes, (std::vector<bool>{true, false}));
  EXPECT_EQ(cells[1].perturbations, (std::vector<std::string>{"camera:tilt-15", "lighting:dim"}));
  EXPECT_EQ(LoadComparedCells(root_ / "sweep/cells/dim").size(), 1u);
}

TEST_F(ComparedCellsTest, NamesTheFileAndTheProblem) {
  std::filesystem::create_directories(root_ / "empty" / "nothing");
  EXPECT_NE(LoadError("empty").find((root_ / "empty").string() + ": holds no cell"), std::string::npos);
  testing::WriteTextFile(root_ / "broken" / "summary.json", "{\"task\": ");
  EXPECT_NE(LoadError("broken").find((root_ / "broken" / "summary.json").string() + ": invalid JSON"),
            std::string::npos)
      << LoadError("broken");
  WriteCell("no_records", "", {true});
  std::filesystem::remove(root_ / "no_records" / "episodes.jsonl");
  EXPECT_NE(LoadError("no_records").find("no episodes.jsonl beside it"), std::string::npos) << LoadError("no_records");
  WriteCell("twice/one", "", {true});
  WriteCell("twice/two", "", {false});
  const std::string twice = LoadError("twice");
  EXPECT_NE(twice.find("two cells of clutter-pick-lift gr1t2 id head s0"), std::string::npos) << twice;
  EXPECT_NE(twice.find((root_ / "twice" / "two" / "summary.json").string()), std::string::npos) << twice;
  WriteCell("bad_levels", R"("perturbations": "lighting:dim", )", {true});
  EXPECT_NE(LoadError("bad_levels").find("key 'perturbations' must be a list"), std::string::npos)
      << LoadError("bad_levels");
}

}  // namespace
}  // namespace tavis::batch::report

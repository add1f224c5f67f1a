// A spec's `sequential:` is read strictly, recorded in the spec's JSON only when given, and laid
// over the cells as groups that stay in one shard.
#include "batch/sweep/sequential_spec.h"

#include <gtest/gtest.h>

#include <string>

#include "batch/output/setting_error.h"
#include "batch/sweep/sequential_plan.h"
#include "configs/yaml_reader.h"

namespace tavis::batch::sweep {
namespace {

const char* kTwoPolicies =
    "tasks: [clutter-pick-cube]\n"
    "robots: [gr1t2]\n"
    "splits: [id]\n"
    "cameras: [head, fixed]\n"
    "seeds: [0, 1]\n"
    "episodes: 30\n"
    "policies:\n"
    "  - {label: expert, name: expert}\n"
    "  - {label: hold, name: hold}\n";

SweepSpec Parse(const std::string& sequential) {
  return ParseSweepSpec(std::string(kTwoPolicies) + sequential, "specs/s.yaml", TAVIS_CONFIG_DIR);
}

std::string ErrorOf(const std::string& sequential) {
  try {
    Parse(sequential);
  } catch (const configs::ConfigError& error) {
    return error.what();
  }
  ADD_FAILURE() << "accepted: " << sequential;
  return "";
}

TEST(SequentialSpec, OffUnlessGivenAndThenInTheSpecsJson) {
  const SweepSpec off = Parse("");
  EXPECT_FALSE(off.sequential.enabled);
  EXPECT_FALSE(SweepSpecJson(off).contains("sequential")) << "a sweep without it records what it always did";
  const SweepSpec defaults = Parse("sequential: {}\n");
  EXPECT_TRUE(defaults.sequential.enabled);
  EXPECT_EQ(defaults.sequential.test.alpha, 0.05);
  EXPECT_EQ(defaults.sequential.test.block, 10);
  EXPECT_EQ(SweepSpecJson(defaults)["sequential"].dump(),
            R"({"alpha":0.05,"block":10,"pairs":["cameras","perturbations"],"policies":[]})");
  const SweepSpec given = Parse("sequential: {alpha: 0.01, block: 5, pairs: [], policies: [[expert, hold]]}\n");
  EXPECT_EQ(given.sequential.test.alpha, 0.01);
  EXPECT_EQ(given.sequential.test.block, 5);
  EXPECT_FALSE(given.sequential.cameras);
  EXPECT_FALSE(given.sequential.perturbations);
  ASSERT_EQ(given.sequential.policies.size(), 1u);
  EXPECT_EQ(given.sequential.policies[0].first, "expert");
}

TEST(SequentialSpec, MistakesAreNamedWithTheKeyAndValue) {
  EXPECT_NE(ErrorOf("sequential: {alpha: 0.7}\n").find("sequential.alpha"), std::string::npos);
  EXPECT_NE(ErrorOf("sequential: {alpha: 0}\n").find("0"), std::string::npos);
  EXPECT_NE(ErrorOf("sequential: {block: 31}\n").find("must be an integer from 1 to 30, got 31"), std::string::npos);
  EXPECT_NE(
      ErrorOf("sequential: {pairs: [policy]}\n").find("unknown pair kind 'policy' (known: cameras, perturbations)"),
      std::string::npos);
  EXPECT_NE(ErrorOf("sequential: {pairs: [cameras, cameras]}\n").find("listed twice"), std::string::npos);
  EXPECT_NE(ErrorOf("sequential: {policies: [[expert, nobody]]}\n")
                .find("no policy has the label 'nobody' (labels: expert, hold)"),
            std::string::npos);
  EXPECT_NE(ErrorOf("sequential: {policies: [[expert, expert]]}\n").find("with itself"), std::string::npos);
  EXPECT_NE(ErrorOf("sequential: {policies: [[expert, hold], [hold, expert]]}\n").find("listed twice"),
            std::string::npos);
  EXPECT_NE(ErrorOf("sequential: {policies: [expert]}\n").find("must name two labels"), std::string::npos);
  EXPECT_NE(ErrorOf("sequential: {pairs: []}\n").find("tests no pair"), std::string::npos);
  EXPECT_NE(ErrorOf("sequential: {alpah: 0.1}\n").find("unknown key 'alpah'"), std::string::npos);
}

// Cells: per seed expert head, expert fixed, hold head, hold fixed (positions 0-3 seed 0... in
// the spec's order: camera, then policy, then seed).
TEST(SequentialSpec, GroupsStayInTheShardOfTheirFirstCell) {
  const SweepSpec spec = Parse("sequential: {pairs: [], policies: [[expert, hold]]}\n");
  const std::vector<SweepCell> cells = ExpandCells(spec, TAVIS_CONFIG_DIR);
  ASSERT_EQ(cells.size(), 8u);
  const SequentialPlan plan = PlanSequential(cells, spec.sequential);
  ASSERT_EQ(plan.groups.size(), 4u) << "expert vs hold per camera and seed";
  for (const std::vector<std::size_t>& group : plan.groups) {
    ASSERT_EQ(group.size(), 2u);
    EXPECT_EQ(cells[group[0]].label, "expert");
    EXPECT_EQ(cells[group[1]].label, "hold");
    EXPECT_EQ(cells[group[0]].config.seed, cells[group[1]].config.seed);
    EXPECT_EQ(plan.shard_position[group[1]], group[0]);
  }
  RequireShardHoldsUnits({0, 4}, plan);
  EXPECT_THROW(RequireShardHoldsUnits({0, 5}, plan), output::SettingError) << "4 groups cannot fill 5 shards";
  const SequentialPlan off = PlanSequential(cells, Parse("").sequential);
  for (std::size_t i = 0; i < cells.size(); ++i) EXPECT_EQ(off.shard_position[i], i);
  RequireShardHoldsUnits({0, 8}, off);
}

// The group stops at the first look where every pair has decided; a cell that holds fewer
// episodes than its group's stop is named.
TEST(SequentialSpec, GroupStopIsTheFirstLookWhereEveryPairDecided) {
  const report::Outcomes wins(30, true), losses(30, false);
  const std::vector<report::SequentialPair> pairs = {{"policy", 0, 1}};
  EXPECT_EQ(GroupStop({wins, losses}, pairs, 30, {0.05, 5}), 10);
  EXPECT_EQ(GroupStop({wins, wins}, pairs, 30, {0.05, 5}), 30) << "undecided: the cap";
  EXPECT_EQ(GroupStop({wins, losses, wins}, {{"camera", 0, 1}, {"camera", 0, 2}}, 30, {0.05, 5}), 30)
      << "a pair that never decides keeps its group to the cap";
}

}  // namespace
}  // namespace tavis::batch::sweep

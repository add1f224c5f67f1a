// `tavis sweep` resumes and merges that must be refused, or must not be blocked, through the real
// program: a rerun whose spec leaves out a dimension of the folder's sweep, a merge of a shard run
// with another robot file (named as such, not as an incomplete shard), a merge that failed and is
// run again, a merge into a shard's own folder, and shard counts that leave shards without cells.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>
#include <string>

#include "tests/tools/tool_runner.h"

namespace tavis::tools::sweep {
namespace {

// 2 cells (head, fixed) of 2 episodes.
const char* kSpec =
    "tasks: [clutter-pick-cube]\n"
    "robots: [gr1t2]\n"
    "splits: [id]\n"
    "cameras: [head, fixed]\n"
    "seeds: [3]\n"
    "episodes: 2\n"
    "envs: 2\n"
    "policy:\n"
    "  name: expert\n";

class SweepResumeAndMerge : public TavisCommandTest {
 protected:
  void SetUp() override {
    TavisCommandTest::SetUp();
    spec_ = WriteSpec("small.yaml", kSpec);
  }
  fs::path WriteSpec(const std::string& name, const std::string& text) const {
    std::ofstream(root_ / name) << text;
    return root_ / name;
  }
  RunResult Sweep(const fs::path& spec, const fs::path& out, const std::string& options = "") const {
    return Run("sweep " + Quote(spec.string()) + " --out " + Quote(out.string()) + " --quiet " + options);
  }
  // The two shards of kSpec, the second run with `config_dir` when given.
  void RunShards(const std::string& second_config_dir = "") const {
    ASSERT_EQ(Sweep(spec_, root_ / "shard0", "--shard 0/2").exit_code, 0);
    const std::string config = second_config_dir.empty() ? "" : " --config-dir " + Quote(second_config_dir);
    const RunResult second = Sweep(spec_, root_ / "shard1", "--shard 1/2" + config);
    ASSERT_EQ(second.exit_code, 0) << second.err;
  }
  RunResult Merge(const fs::path& out) const {
    return Run("sweep merge --out " + Quote(out.string()) + " " + Quote((root_ / "shard0").string()) + " " +
               Quote((root_ / "shard1").string()));
  }

  fs::path spec_;
};

// A rerun whose spec no longer has the folder's perturbations is another sweep (the manifest once
// compared only the keys the new spec has, and such a rerun wrote results over the perturbed cells).
TEST_F(SweepResumeAndMerge, RerunThatLeavesOutThePerturbationsIsRefusedNamingThem) {
  const fs::path perturbed = WriteSpec("perturbed.yaml", std::string(kSpec) + "perturbations: [none, runtime:move]\n");
  const fs::path out = root_ / "sweep";
  ASSERT_EQ(Sweep(perturbed, out).exit_code, 0);
  fs::remove(out / "summary.json");
  fs::remove(out / "cells" / "clutter-pick-cube_gr1t2_id_head_expert.runtime.move_s3" / "summary.json");
  const auto before = Snapshot(out);
  const RunResult rerun = Sweep(spec_, out);
  EXPECT_EQ(rerun.exit_code, 1);
  EXPECT_NE(rerun.err.find("holds another sweep (/spec/perturbations/0 null -> unset"), std::string::npos) << rerun.err;
  EXPECT_NE(rerun.err.find("/spec/perturbations/1/0 \"runtime:move\" -> unset"), std::string::npos) << rerun.err;
  EXPECT_EQ(Snapshot(out), before) << "a refused rerun wrote into the sweep";
}

// Robot file edited for the second shard: its cells are complete, with other settings. The merge
// names the cell, the shard, the key and the shard whose cells have the merge's settings; it once
// called the cell "not complete: rerun that shard".
TEST_F(SweepResumeAndMerge, MergeNamesACompleteCellRunWithOtherSettings) {
  const fs::path edited = root_ / "configs";
  fs::copy(TAVIS_SOURCE_DIR "/configs", edited, fs::copy_options::recursive);
  std::string robot = ReadText(edited / "robots" / "gr1t2.yaml");
  robot.replace(robot.find("arm: {velocity_limit: 5.0"), 25, "arm: {velocity_limit: 4.0");
  std::ofstream(edited / "robots" / "gr1t2.yaml", std::ios::trunc) << robot;
  RunShards(edited.string());
  const RunResult merged = Merge(root_ / "merged");
  EXPECT_EQ(merged.exit_code, 1);
  EXPECT_NE(merged.err.find("cell clutter-pick-cube_gr1t2_id_fixed_expert_s3 of shard " + (root_ / "shard1").string() +
                            " is complete but ran with other settings"),
            std::string::npos)
      << merged.err;
  EXPECT_NE(merged.err.find("arm.velocity_limit \"4.0\" -> \"5.0\""), std::string::npos) << merged.err;
  EXPECT_NE(merged.err.find("the cells of shard " + (root_ / "shard0").string() + " have this merge's settings"),
            std::string::npos)
      << merged.err;
  EXPECT_EQ(merged.err.find("not complete"), std::string::npos) << merged.err;
  EXPECT_FALSE(fs::exists(root_ / "merged"));
}

// A merge that fails part-way (a cell's folder holds a file that cannot be copied) leaves OUT
// holding no results and nothing beside it: the same command, once the cause is gone, merges.
TEST_F(SweepResumeAndMerge, FailedMergeDoesNotBlockTheSameCommand) {
  RunShards();
  const fs::path fifo = root_ / "shard1" / "cells" / "clutter-pick-cube_gr1t2_id_fixed_expert_s3" / "pipe";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0644), 0);
  const fs::path out = root_ / "merged";
  const RunResult failed = Merge(out);
  EXPECT_EQ(failed.exit_code, 1);
  for (const auto& entry : fs::directory_iterator(out)) {
    const std::string name = entry.path().filename().string();
    EXPECT_TRUE(name == ".tavis_output" || name == ".tavis_lock") << "a failed merge left " << entry.path();
  }
  for (const auto& entry : fs::directory_iterator(root_)) {
    EXPECT_EQ(entry.path().filename().string().find(".merged.tavis-"), std::string::npos)
        << "a failed merge left " << entry.path();
  }
  fs::remove(fifo);
  const RunResult again = Merge(out);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_TRUE(fs::exists(out / "summary.json"));
  EXPECT_TRUE(fs::exists(out / "cells" / "clutter-pick-cube_gr1t2_id_fixed_expert_s3" / "summary.json"));
}

// --out inside a shard (it once copied a cell into itself 158 levels deep) or equal to one.
TEST_F(SweepResumeAndMerge, MergeIntoAShardsFolderIsRefusedNamingBoth) {
  RunShards();
  const fs::path cell = root_ / "shard0" / "cells" / "clutter-pick-cube_gr1t2_id_head_expert_s3";
  const auto before = Snapshot(root_ / "shard0");
  const RunResult inside = Merge(cell / "merged");
  EXPECT_EQ(inside.exit_code, 1);
  EXPECT_NE(inside.err.find("--out " + (cell / "merged").string() + " is inside the shard folder " +
                            (root_ / "shard0").string()),
            std::string::npos)
      << inside.err;
  EXPECT_FALSE(fs::exists(cell / "merged"));
  const RunResult same = Merge(root_ / "shard1");
  EXPECT_EQ(same.exit_code, 1);
  EXPECT_NE(same.err.find("is the shard folder " + (root_ / "shard1").string()), std::string::npos) << same.err;
  EXPECT_EQ(Snapshot(root_ / "shard0"), before);
}

// N above the number of cells leaves shards with nothing to run (0/1000000 was refused as if it were
// not I/N; 2/3 of two cells ran an empty shard and said it was complete).
TEST_F(SweepResumeAndMerge, MoreShardsThanCellsAreRefused) {
  for (const char* shard : {"0/1000000", "2/3"}) {
    const RunResult run = Sweep(spec_, root_ / "out", std::string("--shard ") + shard);
    EXPECT_EQ(run.exit_code, 1) << shard;
    EXPECT_NE(run.err.find(std::string("--shard '") + shard + "' splits the sweep's 2 cells into "), std::string::npos)
        << run.err;
    EXPECT_NE(run.err.find("N must be 1 to 2"), std::string::npos) << run.err;
    EXPECT_FALSE(fs::exists(root_ / "out"));
  }
}

// One of a kind is said in the singular: "merged 1 shard", "1 cell of 1 policy", "(1 cell)".
TEST_F(SweepResumeAndMerge, MessagesCountOneInTheSingular) {
  std::string one = kSpec;
  one.replace(one.find("[head, fixed]"), 13, "[head]");
  ASSERT_EQ(Sweep(WriteSpec("one.yaml", one), root_ / "shard", "--shard 0/1").exit_code, 0);
  const RunResult merged =
      Run("sweep merge --out " + Quote((root_ / "merged").string()) + " " + Quote((root_ / "shard").string()));
  ASSERT_EQ(merged.exit_code, 0) << merged.err;
  EXPECT_NE(merged.out.find("merged 1 shard into"), std::string::npos) << merged.out;
  EXPECT_NE(ReadText(root_ / "merged" / "report.html").find("<p>1 cell of 1 policy, 2 episodes per cell"),
            std::string::npos);

  std::string two_labels = one;
  two_labels.replace(two_labels.find("policy:\n  name: expert\n"), 24,
                     "policies:\n  - {label: a, name: expert}\n  - {label: b, name: expert}\n");
  ASSERT_EQ(Sweep(WriteSpec("two.yaml", two_labels), root_ / "two").exit_code, 0);
  const RunResult table = Run("table --in " + Quote((root_ / "two" / "cells").string()) + " --suite tavis-head --out " +
                              Quote((root_ / "table").string()));
  EXPECT_EQ(table.exit_code, 1);
  EXPECT_NE(table.err.find("a (1 cell), b (1 cell)"), std::string::npos) << table.err;
}

}  // namespace
}  // namespace tavis::tools::sweep

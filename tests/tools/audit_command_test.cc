// `tavis audit`: errors, the printed table and DIR/audit.json.
#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tool_runner.h"

namespace tavis::tools {
namespace {

using AuditCommand = TavisCommandTest;

TEST_F(AuditCommand, UnknownTaskFailsNamingIt) {
  const RunResult run = Run("audit --task fly-to-moon");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("'fly-to-moon'"), std::string::npos) << run.err;
  EXPECT_EQ(run.out, "");
}

TEST_F(AuditCommand, BadImageSizeFailsNamingIt) {
  const RunResult run = Run("audit --image-size 224by224");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("'224by224'"), std::string::npos) << run.err;
}

TEST_F(AuditCommand, SmallRunPrintsTheTableAndWritesAuditJson) {
  const fs::path dir = root_ / "audit";
  fs::create_directories(dir);
  const fs::path other = dir / "notes.txt";
  { std::ofstream(other) << "kept"; }
  const RunResult run =
      Run("audit --task conditional-pick --episodes 2 --image-size 64x64 --out " + Quote(dir.string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;

  const std::vector<std::string> lines = Lines(run.out);
  ASSERT_EQ(lines.size(), 2u + 2u * 4u) << run.out;  // title, header, 2 objects x 4 cameras
  EXPECT_EQ(lines[0], "conditional-pick gr1t2 id, 2 episodes, 64x64, visible = >=1% of the object's pixels");
  EXPECT_EQ(lines[1].rfind("object", 0), 0u) << lines[1];
  EXPECT_EQ(lines[2].rfind("target        head ", 0), 0u) << lines[2];
  EXPECT_EQ(lines[6].rfind("cue_card      head ", 0), 0u) << lines[6];
  EXPECT_NE(run.err.find("audit: conditional-pick gr1t2 id: 2 episodes"), std::string::npos) << run.err;

  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.insert(entry.path().filename().string());
  EXPECT_EQ(names, (std::set<std::string>{"audit.json", "notes.txt"}));
  EXPECT_EQ(ReadText(other), "kept");

  const nlohmann::json audit = nlohmann::json::parse(ReadText(dir / "audit.json"));
  for (const char* key :
       {"split", "seed", "episodes", "image_width", "image_height", "visible", "visible_fraction", "cells"}) {
    EXPECT_TRUE(audit.contains(key)) << key << " missing";
  }
  EXPECT_EQ(audit.at("visible_fraction").get<double>(), 0.01);
  ASSERT_EQ(audit.at("cells").size(), 1u);
  const nlohmann::json& cell = audit.at("cells")[0];
  EXPECT_EQ(cell.at("task"), "conditional-pick");
  EXPECT_EQ(cell.at("robot"), "gr1t2");
  ASSERT_EQ(cell.at("summary").size(), 8u);
  for (const char* key : {"object", "camera", "visible_at_reset", "fixated", "visible_at_fixation"}) {
    EXPECT_TRUE(cell.at("summary")[0].contains(key)) << key << " missing";
  }
  ASSERT_EQ(cell.at("episodes").size(), 2u);
  const nlohmann::json& card = cell.at("episodes")[1].at("objects").at("cue_card");
  for (const char* camera : {"head", "fixed", "left_wrist", "right_wrist"}) {
    EXPECT_TRUE(card.at("at_reset").contains(camera)) << camera;
  }
  EXPECT_TRUE(card.contains("at_fixation"));
  EXPECT_TRUE(card.contains("fixation_tick"));
}

// --perturb runs the audit's scene under the level and audit.json names it; an unknown level is
// refused naming it before anything is written.
TEST_F(AuditCommand, PerturbRunsUnderTheLevelAndRecordsIt) {
  const fs::path dir = root_ / "perturbed";
  const RunResult run =
      Run("audit --task clutter-pick-cube --episodes 1 --image-size 32x32 --quiet "
          "--perturb camera:fixed-view-large --out " +
          Quote(dir.string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json audit = nlohmann::json::parse(ReadText(dir / "audit.json"));
  EXPECT_EQ(audit.at("perturbations"), nlohmann::json::array({"camera:fixed-view-large"}));

  const fs::path bad = root_ / "bad";
  const RunResult refused = Run("audit --episodes 1 --perturb camera:sideways --out " + Quote(bad.string()));
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_NE(refused.err.find("no level 'sideways'"), std::string::npos) << refused.err;
  EXPECT_FALSE(fs::exists(bad));
}

TEST_F(AuditCommand, AllRefusesATask) {
  const RunResult run = Run("audit --all --task conditional-pick --episodes 1");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("--all"), std::string::npos) << run.err;
}

}  // namespace
}  // namespace tavis::tools

// The table that declares a cell's settings: each key and flag once, the records it makes exactly
// those earlier versions wrote (so that their cells still resume and compare), the checks naming
// a setting by its key.
#include "batch/cell/cell_settings.h"

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "tests/batch/cell/example_cells.h"

namespace tavis::batch::cell {
namespace {

// The message of the output::SettingError `check` throws, which must name `key`.
template <typename Check>
std::string SettingErrorOf(Check&& check, const std::string& key) {
  try {
    check();
  } catch (const output::SettingError& error) {
    EXPECT_EQ(error.key(), key) << error.what();
    return error.what();
  }
  ADD_FAILURE() << "no error naming " << key;
  return "";
}

TEST(CellSettings, EachKeySpecKeyAndFlagIsDeclaredOnce) {
  std::set<std::string> keys;
  std::set<std::string> spec_keys;
  std::map<std::string, std::set<std::string>> settings_of_flag;
  for (const CellSetting& setting : CellSettings()) {
    EXPECT_TRUE(keys.insert(setting.key).second) << setting.key;
    if (setting.spec_key != nullptr) {
      EXPECT_TRUE(spec_keys.insert(setting.spec_key).second) << setting.spec_key;
    }
    if (setting.in_manifest) {
      EXPECT_NE(setting.spec_key, nullptr) << setting.key;
    }
    if (setting.option != EvalOption::kNone) {
      ASSERT_NE(setting.flag, nullptr) << setting.key;
      EXPECT_FALSE(setting.help.empty()) << setting.key;
      settings_of_flag[setting.flag].insert(setting.key);
    }
    EXPECT_EQ(&CellSettingNamed(setting.key), &setting);
  }
  for (const auto& [flag, settings] : settings_of_flag) {
    // One flag gives both image sizes (WIDTHxHEIGHT); every other flag is one setting's.
    if (flag == "--image-size") {
      EXPECT_EQ(settings, (std::set<std::string>{"image_width", "image_height"}));
    } else {
      EXPECT_EQ(settings.size(), 1u) << flag;
    }
  }
  EXPECT_EQ(FindCellSetting("no_such_setting"), nullptr);
}

// cell.json as this program wrote it before the table existed (its identity aside): the same keys,
// values and number types, so that its cells still --resume.
TEST(CellSettings, CellJsonHoldsWhatEarlierVersionsWrote) {
  EvaluationCellConfig expert;
  EXPECT_EQ(RecordedSettingsJson(expert, CellRecord::kCellJson, false).dump(),
            R"({"actions_file":"","camera":"head","episodes":96,"expert_hz":60,"expert_mode":"gaze-first",)"
            R"("image_height":0,"image_width":0,"observation_dataset":"","observation_keys":"tavis",)"
            R"("policy":"expert","render_cameras":[],"replan_steps":0,"robot":"gr1t2","seed":0,"servers":[],)"
            R"("split":"id","task":"clutter-pick-cube"})");

  EvaluationCellConfig hold = HoldCellOnReachy();
  hold.render_cameras = {"head", "left_wrist"};
  hold.image_width = 64;
  hold.image_height = 48;
  hold.episode_start = 3;
  hold.episodes = 1;
  hold.envs = 7;  // how it runs, not what it records
  EXPECT_EQ(RecordedSettingsJson(hold, CellRecord::kCellJson, false).dump(),
            R"({"actions_file":"","camera":"fixed","episode_start":3,"episodes":1,"expert_hz":60,)"
            R"("image_height":48,"image_width":64,"observation_dataset":"","observation_keys":"tavis",)"
            R"("policy":"hold","render_cameras":["head","left_wrist"],"replan_steps":0,"robot":"reachy2",)"
            R"("seed":18446744073709551615,"servers":[],"split":"ood-init-pose","task":"wait-then-act"})");

  EvaluationCellConfig served = ServedCellWithOptions();  // serving batched: the records do not depend on it
  served.server_ready_timeout_s = 3;                      // nor on these
  served.reply_timeout_s = 9;
  served.max_reply_mb = 2;
  EXPECT_EQ(RecordedSettingsJson(served, CellRecord::kCellJson, true).dump(),
            R"({"actions_file":"","camera":"head","episodes":96,"expert_hz":60,"image_height":0,"image_width":0,)"
            R"("observation_dataset":"/data/set","observation_keys":"aloha","policy":"openpi","render_cameras":[],)"
            R"("replan_steps":5,"robot":"gr1t2","seed":0,"servers":["ws://a:1","ws://b:2"],"split":"id",)"
            R"("task":"clutter-pick-cube"})");
  // summary.json: the settings beside the results, a served policy's where it served.
  EXPECT_EQ(RecordedSettingsJson(served, CellRecord::kSummary, true).dump(),
            R"({"actions_file":"","camera":"head","config_dir":"","expert_hz":60,"observation_dataset":"/data/set",)"
            R"("policy":"openpi","replan_steps":5,"robot":"gr1t2","seed":0,"servers":["ws://a:1","ws://b:2"],)"
            R"("serving":"batched","split":"id","task":"clutter-pick-cube"})");
  EXPECT_EQ(RecordedSettingsJson(expert, CellRecord::kSummary, false).dump(),
            R"({"actions_file":"","camera":"head","config_dir":"","expert_hz":60,"expert_mode":"gaze-first",)"
            R"("policy":"expert","robot":"gr1t2","seed":0,"split":"id","task":"clutter-pick-cube"})");
}

TEST(CellSettings, ValuesOutOfRangeOrForAnotherPolicyAreNamedByKey) {
  EvaluationCellConfig config;
  EXPECT_NO_THROW(CheckSettingValues(config));
  config.episodes = 0;
  EXPECT_EQ(SettingErrorOf([&] { CheckSettingValues(config); }, "episodes"), "episodes must be at least 1, got 0");
  config = {};
  config.envs = 5000;
  EXPECT_EQ(SettingErrorOf([&] { CheckSettingValues(config); }, "envs"), "envs must be at most 4096, got 5000");
  config = {};
  config.expert_hz = 30;
  EXPECT_EQ(SettingErrorOf([&] { CheckSettingValues(config); }, "expert_hz"), "expert_hz must be 60 or 20, got 30");
  config = {};
  config.replan_steps = 5;
  EXPECT_EQ(SettingErrorOf([&] { CheckSettingValues(config); }, "replan_steps"),
            "replan_steps applies to policy 'openpi' only, got policy 'expert'");
  config.policy = "openpi";
  EXPECT_NO_THROW(CheckSettingValues(config));
  config.max_reply_mb = 0.0005;
  EXPECT_EQ(SettingErrorOf([&] { CheckSettingValues(config); }, "max_reply_mb"),
            "max_reply_mb must be at least 0.001 MiB, got 0.0005");
  config = {};
  config.policy = "hold";
  config.expert_mode = scenarios::expert::ExpertMode::kHeadStill;
  EXPECT_EQ(SettingErrorOf([&] { CheckSettingValues(config); }, "expert_mode"),
            "expert_mode applies to policy 'expert' only, got policy 'hold'");
  config.expert_mode = scenarios::expert::ExpertMode::kGazeFirst;  // its default: allowed
  EXPECT_NO_THROW(CheckSettingValues(config));
}

TEST(CellSettings, ValuesAreCopiedAndComparedWithTheirDefaultsByTheTable) {
  const CellSetting& servers = CellSettingNamed("servers");
  EvaluationCellConfig from;
  EvaluationCellConfig to;
  from.servers = {"ws://h:1"};
  EXPECT_FALSE(HasDefaultValue(servers, from));
  EXPECT_TRUE(HasDefaultValue(servers, to));
  CopySetting(servers, from, to);
  EXPECT_EQ(to.servers, from.servers);
  EXPECT_EQ(SettingJson(CellSettingNamed("serving"), to), "serial");
  EXPECT_TRUE(SettingApplies(SettingScope::kServed, "openpi"));
  EXPECT_FALSE(SettingApplies(SettingScope::kServed, "expert"));
  EXPECT_TRUE(SettingApplies(SettingScope::kAnyPolicy, "replay"));
  EXPECT_STREQ(ScopePolicyName(SettingScope::kReplay), "replay");
}

// A record read back gives the settings it was written from (tavis verify reads cell.json so);
// cell.json's perturbation levels, objects with their settings, read as AXIS:LEVEL.
TEST(CellSettings, ARecordReadsBackIntoTheSettingsItWasWrittenFrom) {
  EvaluationCellConfig written;
  written.task = "wait-then-act";
  written.split = scenarios::Split::kOodSpatial;
  written.camera = CameraProtocol::kFixed;
  written.policy = "openpi";
  written.servers = {"ws://h:1"};
  written.seed = 18446744073709551615ull;
  written.episode_start = 7;
  written.image_width = 32;
  written.image_height = 24;
  written.perturbations = {"lighting:dim"};
  nlohmann::json record = RecordedSettingsJson(written, CellRecord::kCellJson, true);
  EvaluationCellConfig read;
  ReadRecordedSettings(record, read);
  EXPECT_EQ(RecordedSettingsJson(read, CellRecord::kCellJson, true), record);
  EXPECT_EQ(read.seed, written.seed);
  record["perturbations"] = {{{"axis", "lighting"}, {"level", "dim"}, {"settings", {{"scale", 0.5}}}}};
  record["identity"] = {{"program_version", "v1"}};  // no setting's key: skipped
  EvaluationCellConfig from_cell_json;
  ReadRecordedSettings(record, from_cell_json);
  EXPECT_EQ(from_cell_json.perturbations, std::vector<std::string>{"lighting:dim"});
  record["seed"] = "zero";
  try {
    ReadRecordedSettings(record, from_cell_json);
    ADD_FAILURE() << "a seed that is no number was read";
  } catch (const std::invalid_argument& error) {
    EXPECT_EQ(std::string(error.what()).rfind("seed: cannot read \"zero\": type must be number", 0), 0u)
        << error.what();
  }
}

}  // namespace
}  // namespace tavis::batch::cell

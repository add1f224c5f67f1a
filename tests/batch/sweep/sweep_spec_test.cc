// Sweep specs are read strictly: every kind of mistake names the file, the key and the value.
#include "batch/sweep/sweep_spec.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <ostream>
#include <string>

#include "batch/output/setting_error.h"
#include "configs/yaml_reader.h"

namespace tavis::batch::sweep {
namespace {

const char* kValid =
    "tasks: [clutter-pick-cube]\n"
    "robots: [gr1t2]\n"
    "splits: [id, ood-spatial]\n"
    "cameras: [head, fixed]\n"
    "seeds: [0, 7]\n"
    "episodes: 3\n"
    "policy:\n"
    "  name: expert\n";

SweepSpec Parse(const std::string& text) { return ParseSweepSpec(text, "specs/bad.yaml", TAVIS_CONFIG_DIR); }

// The error for `text`, which must be refused.
std::string ErrorOf(const std::string& text) {
  try {
    Parse(text);
  } catch (const configs::ConfigError& error) {
    return error.what();
  }
  ADD_FAILURE() << "accepted:\n" << text;
  return "";
}

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(SweepSpec, ExpandsTheProductInSpecOrder) {
  const SweepSpec spec = Parse(kValid);
  const std::vector<SweepCell> cells = ExpandCells(spec, TAVIS_CONFIG_DIR);
  ASSERT_EQ(cells.size(), 8U);
  EXPECT_EQ(cells[0].id, "clutter-pick-cube_gr1t2_id_head_expert_s0");
  EXPECT_EQ(cells[1].id, "clutter-pick-cube_gr1t2_id_head_expert_s7");
  EXPECT_EQ(cells[2].id, "clutter-pick-cube_gr1t2_id_fixed_expert_s0");
  EXPECT_EQ(cells[7].id, "clutter-pick-cube_gr1t2_ood-spatial_fixed_expert_s7");
  EXPECT_EQ(cells[7].config.episodes, 3);
  EXPECT_EQ(cells[7].config.seed, 7U);
}

TEST(SweepSpec, PerturbationsAreADimensionWhoseCellsCarryTheirLevelsInTheirLabels) {
  const std::string text =
      std::string(kValid) + "perturbations: [none, camera:fov-wide, sensor:noise-low+lighting:dim]\n";
  const SweepSpec spec = Parse(text);
  ASSERT_EQ(spec.perturbations.size(), 3u);
  const std::vector<SweepCell> cells = ExpandCells(spec, TAVIS_CONFIG_DIR);
  ASSERT_EQ(cells.size(), 24U);
  // Order: ... policy, perturbation, seed; the base cell keeps its id and label.
  EXPECT_EQ(cells[0].id, "clutter-pick-cube_gr1t2_id_head_expert_s0");
  EXPECT_EQ(cells[0].label, "expert");
  EXPECT_TRUE(cells[0].config.perturbations.empty());
  EXPECT_EQ(cells[2].id, "clutter-pick-cube_gr1t2_id_head_expert.camera.fov-wide_s0");
  EXPECT_EQ(cells[2].label, "expert.camera.fov-wide");
  EXPECT_EQ(cells[2].config.perturbations, std::vector<std::string>{"camera:fov-wide"});
  EXPECT_EQ(cells[5].label, "expert.sensor.noise-low.lighting.dim");
  EXPECT_EQ(cells[5].config.perturbations, (std::vector<std::string>{"sensor:noise-low", "lighting:dim"}));
  EXPECT_EQ(cells[5].config.seed, 7U);
  const nlohmann::ordered_json json = SweepSpecJson(spec);
  ASSERT_TRUE(json.contains("perturbations"));
  EXPECT_EQ(json["perturbations"].size(), 3u);
  // A spec without the dimension is the base scene alone, and its manifest is as before.
  const SweepSpec plain = Parse(kValid);
  EXPECT_EQ(plain.perturbations, std::vector<std::vector<std::string>>{{}});
  EXPECT_FALSE(SweepSpecJson(plain).contains("perturbations"));
}

// A merge of finished shards re-reads the spec without the files its policies named (they may
// live on the machine that ran the cells only).
TEST(SweepSpec, PolicyFilesAreNotReadWhenAskedNotTo) {
  const std::string spec = Replace(kValid, "name: expert", "name: replay\n  actions: /nonexistent/a.csv");
  EXPECT_EQ(
      ParseSweepSpec(spec, "specs/bad.yaml", TAVIS_CONFIG_DIR, PolicyFiles::kNotRead).policies[0].settings.actions_file,
      "/nonexistent/a.csv");
}

TEST(SweepSpec, SuitesBringTheirTasksOnce) {
  const SweepSpec spec = Parse(
      Replace(kValid, "tasks: [clutter-pick-cube]", "suites: [tavis-head, tavis-hands]\ntasks: [clutter-pick-cube]"));
  EXPECT_EQ(spec.tasks.size(), 8U);
}

TEST(SweepSpec, ShardsPartitionTheCells) {
  EXPECT_EQ(ParseShard("2/3").index, 2);
  int held = 0;
  for (std::size_t cell = 0; cell < 10; ++cell) {
    for (int index = 0; index < 3; ++index) held += InShard(cell, {index, 3}) ? 1 : 0;
  }
  EXPECT_EQ(held, 10);
  for (const char* bad : {"3/3", "1", "-1/3", "a/b", "0/0", "1/2/3"}) {
    try {
      ParseShard(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const output::SettingError& error) {
      EXPECT_EQ(error.key(), "shard") << "named by its key, not tavis sweep's flag: " << error.what();
      EXPECT_NE(error.problem().find(std::string("'") + bad + "'"), std::string::npos) << error.what();
    }
  }
}

// Two labelled policies: expert on every cell, hold only on reachy2's head cells; three
// checkpoints of one recipe.
const char* kLabelled =
    "tasks: [clutter-pick-cube, wait-then-act]\n"
    "robots: [gr1t2, reachy2]\n"
    "splits: [id]\n"
    "cameras: [head, fixed]\n"
    "seeds: [0]\n"
    "episodes: 3\n"
    "policies:\n"
    "  - label: expert-a\n"
    "    name: expert\n"
    "    seed_group: recipe\n"
    "  - label: expert-b\n"
    "    name: expert\n"
    "    seed_group: recipe\n"
    "  - label: still\n"
    "    name: hold\n"
    "    cells: {robots: [reachy2], cameras: [head]}\n"
    "figures:\n"
    "  single_vs_multi: [still, recipe]\n"
    "  galt_window_s: 4.0\n";

TEST(SweepSpec, LabelledPoliciesServeTheirCells) {
  const SweepSpec spec = Parse(kLabelled);
  ASSERT_EQ(spec.policies.size(), 3U);
  EXPECT_EQ(spec.policies[2].label, "still");
  const std::vector<SweepCell> cells = ExpandCells(spec, TAVIS_CONFIG_DIR);
  // 2 tasks x 2 robots x 2 cameras for each expert label, 2 tasks x reachy2 head for hold.
  ASSERT_EQ(cells.size(), 8U * 2U + 2U);
  int still = 0;
  for (const SweepCell& cell : cells) {
    EXPECT_NE(cell.id.find("_" + cell.label + "_s0"), std::string::npos) << cell.id;
    if (cell.label != "still") {
      EXPECT_EQ(cell.seed_group, "recipe");
      EXPECT_EQ(cell.config.policy, "expert");
      continue;
    }
    ++still;
    EXPECT_EQ(cell.config.policy, "hold");
    EXPECT_EQ(cell.config.robot, "reachy2");
    EXPECT_EQ(cell.config.camera, CameraProtocol::kHead);
  }
  EXPECT_EQ(still, 2);
  EXPECT_EQ(cells[0].id, "clutter-pick-cube_gr1t2_id_head_expert-a_s0");
  EXPECT_EQ(cells[1].id, "clutter-pick-cube_gr1t2_id_head_expert-b_s0");
  EXPECT_EQ(spec.figures["single_vs_multi"][1], "recipe");
  EXPECT_DOUBLE_EQ(spec.figures["galt_window_s"].get<double>(), 4.0);
  EXPECT_EQ(SweepSpecJson(spec)["policies"][2]["cells"]["robots"][0], "reachy2");
}

// figures.galt_reference_datasets maps the sweep's TAVIS-Head tasks to LeRobot dataset folders,
// each checked for its meta/info.json when the spec is read.
TEST(SweepSpec, Figure4DatasetReferencesNameTheSweepsHeadTasks) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("tavis_spec_reference_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir / "meta");
  std::ofstream(dir / "meta" / "info.json") << "{}";
  const std::string spec =
      std::string(kLabelled) + "  galt_reference_datasets: {wait-then-act: " + dir.string() + "}\n";
  const SweepSpec parsed = Parse(spec);
  EXPECT_EQ(parsed.figures["galt_reference_datasets"]["wait-then-act"], dir.string());
  EXPECT_EQ(SweepSpecJson(parsed)["figures"]["galt_reference_datasets"]["wait-then-act"], dir.string());
  const auto error = [&spec](const std::string& from, const std::string& to) {
    return ErrorOf(Replace(spec, from, to));
  };
  EXPECT_NE(error("{wait-then-act:", "{multi-shelf-scan:")
                .find("figures.galt_reference_datasets.multi-shelf-scan: the sweep does not evaluate "
                      "multi-shelf-scan"),
            std::string::npos);
  const std::string hands = Replace(spec, "tasks: [clutter-pick-cube, wait-then-act]",
                                    "tasks: [clutter-pick-cube, wait-then-act, peeking-box]");
  EXPECT_NE(ErrorOf(Replace(hands, "{wait-then-act:", "{peeking-box:"))
                .find("Figure 4 draws TAVIS-Head tasks only, not peeking-box"),
            std::string::npos);
  EXPECT_NE(error("{wait-then-act:", "{pick-nothing:")
                .find("figures.galt_reference_datasets.pick-nothing: unknown key 'pick-nothing'"),
            std::string::npos);
  EXPECT_NE(error(dir.string() + "}", (dir / "nowhere").string() + "}")
                .find("is not a LeRobot dataset (no meta/info.json there)"),
            std::string::npos);
  EXPECT_NE(
      error("galt_reference_datasets:", "galt_reference: still\n  galt_reference_datasets:").find("give one of them"),
      std::string::npos);
  EXPECT_NE(error("{wait-then-act: " + dir.string() + "}", "{}").find("at least one"), std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST(SweepSpec, LabelledPolicyMistakesAreNamed) {
  const auto error = [](const std::string& from, const std::string& to) {
    return ErrorOf(Replace(kLabelled, from, to));
  };
  EXPECT_NE(error("label: expert-b", "label: expert-a").find("policies[1].label: 'expert-a' is used twice"),
            std::string::npos);
  EXPECT_NE(error("  - label: still\n    name: hold\n", "  - name: hold\n").find("policies[2]: needs label"),
            std::string::npos);
  EXPECT_NE(error("label: still", "label: still/1").find("still/1"), std::string::npos);
  EXPECT_NE(error("[still, recipe]", "[still, nobody]")
                .find("figures.single_vs_multi[1]: no policy has the label or seed group 'nobody'"),
            std::string::npos);
  EXPECT_NE(error("[still, recipe]", "[still]").find("figures.single_vs_multi"), std::string::npos);
  EXPECT_NE(error("galt_window_s: 4.0", "galt_window_s: 5").find("figures.galt_window_s"), std::string::npos);
  EXPECT_NE(error("robots: [reachy2]", "robots: [atlas]").find("policies[2].cells.robots[0]: unknown robot 'atlas'"),
            std::string::npos);
  EXPECT_NE(error("cameras: [head]}", "camera: [head]}").find("camera"), std::string::npos);
  EXPECT_NE(error("policies:\n", "policy:\n  name: expert\npolicies:\n").find("exactly one of policy"),
            std::string::npos);
}

struct BadSpec {
  const char* name;
  const char* from;
  const char* to;
  const char* key;    // the key path the message names
  const char* value;  // the bad value it quotes
};

void PrintTo(const BadSpec& bad, std::ostream* out) { *out << bad.name; }

class SweepSpecErrors : public ::testing::TestWithParam<BadSpec> {};

TEST_P(SweepSpecErrors, NameFileKeyAndValue) {
  const BadSpec& bad = GetParam();
  const std::string error = ErrorOf(Replace(kValid, bad.from, bad.to));
  EXPECT_NE(error.find("specs/bad.yaml"), std::string::npos) << error;
  EXPECT_NE(error.find(bad.key), std::string::npos) << error;
  EXPECT_NE(error.find(bad.value), std::string::npos) << error;
}

INSTANTIATE_TEST_SUITE_P(
    Mistakes, SweepSpecErrors,
    ::testing::Values(
        BadSpec{"UnknownKey", "episodes: 3", "episodes: 3\nepisode: 4", "episode", "episode"},
        BadSpec{"UnknownTask", "[clutter-pick-cube]", "[clutter-pick-cub]", "tasks[0]", "clutter-pick-cub"},
        BadSpec{"UnknownSuite", "tasks: [clutter-pick-cube]", "suites: [tavis-feet]", "suites[0]", "tavis-feet"},
        BadSpec{"UnknownRobot", "[gr1t2]", "[gr1t2, atlas]", "robots[1]", "atlas"},
        BadSpec{"UnknownSplit", "[id, ood-spatial]", "[id, ood]", "splits[1]", "'ood'"},
        BadSpec{"UnknownCamera", "[head, fixed]", "[head, wrist]", "cameras[1]", "wrist"},
        BadSpec{"RepeatedCamera", "[head, fixed]", "[head, head]", "cameras[1]", "head"},
        BadSpec{"NegativeSeed", "[0, 7]", "[0, -7]", "seeds[1]", "-7"},
        BadSpec{"SeedTooLarge", "[0, 7]", "[18446744073709551616]", "seeds[0]", "18446744073709551616"},
        BadSpec{"ZeroEpisodes", "episodes: 3", "episodes: 0", "episodes", "got 0"},
        BadSpec{"TextEpisodes", "episodes: 3", "episodes: many", "episodes", "many"},
        BadSpec{"EmptyRobots", "[gr1t2]", "[]", "robots", "[]"},
        BadSpec{"UnknownPolicy", "name: expert", "name: oracle", "policy.name", "oracle"},
        BadSpec{"ReplayWithoutActions", "name: expert", "name: replay", "policy", "replay"},
        BadSpec{"ServersForExpert", "name: expert", "name: expert\n  servers: [ws://x:1]", "policy.servers", "expert"},
        BadSpec{"UnknownPolicyKey", "name: expert", "name: expert\n  temperature: 2", "policy", "temperature"},
        BadSpec{"MissingRobots", "robots: [gr1t2]\n", "", "robots", "robots"},
        BadSpec{"UnknownPerturbationLevel", "episodes: 3", "episodes: 3\nperturbations: [none, camera:sideways]",
                "perturbations[1]", "'sideways'"},
        BadSpec{"UnknownPerturbationAxis", "episodes: 3", "episodes: 3\nperturbations: [weather:rain]",
                "perturbations[0]", "'weather'"},
        BadSpec{"RepeatedPerturbation", "episodes: 3",
                "episodes: 3\nperturbations: [sensor:noise-low, sensor:noise-low]", "perturbations[1]", "noise-low"},
        BadSpec{"PerturbationAxisTwice", "episodes: 3",
                "episodes: 3\nperturbations: [sensor:noise-low+sensor:blur-low]", "perturbations[0]", "already chosen"},
        // The files a policy names are read with the spec, not when its first cell starts.
        BadSpec{"MissingActionsFile", "name: expert", "name: replay\n  actions: /nonexistent/a.csv", "policy.actions",
                "/nonexistent/a.csv: no such file"},
        BadSpec{"ActionsFileIsADevice", "name: expert", "name: replay\n  actions: /dev/zero", "policy.actions",
                "/dev/zero: is a character device"},
        BadSpec{"MissingKeysFile", "name: expert", "name: openpi\n  servers: [ws://x:1]\n  keys: /nonexistent/k.yaml",
                "policy.keys", "'/nonexistent/k.yaml' are neither a preset"},
        BadSpec{"MissingMatchDataset", "name: expert",
                "name: openpi\n  servers: [ws://x:1]\n  match_dataset: /nonexistent/d", "policy.match_dataset",
                "'/nonexistent/d' is not a LeRobot dataset: /nonexistent/d/meta/info.json: no such file"}),
    [](const ::testing::TestParamInfo<BadSpec>& case_info) { return std::string(case_info.param.name); });

// A typo'd key is named as unknown, with the key it was probably meant to be and the known keys,
// wherever it is; it was once reported as the key it meant being missing ("missing key 'robots'").
TEST(SweepSpec, ATypoedKeyIsNamedWithTheNearestKnownKey) {
  const std::string root = ErrorOf(Replace(kValid, "robots:", "robot:"));
  EXPECT_NE(root.find("specs/bad.yaml: robot: unknown key 'robot' (did you mean 'robots'?); known keys: "),
            std::string::npos)
      << root;
  EXPECT_NE(root.find("cameras, envs, episodes, figures"), std::string::npos) << root;
  EXPECT_EQ(root.find("missing"), std::string::npos) << root;
  const std::string policy = ErrorOf(Replace(kValid, "  name: expert", "  nmae: expert"));
  EXPECT_NE(policy.find("policy.nmae: unknown key 'nmae' (did you mean 'name'?)"), std::string::npos) << policy;
  const std::string filter = ErrorOf(Replace(kLabelled, "cells: {robots:", "cells: {robts:"));
  EXPECT_NE(filter.find("policies[2].cells.robts: unknown key 'robts' (did you mean 'robots'?)"), std::string::npos)
      << filter;
  const std::string figures = ErrorOf(Replace(kLabelled, "galt_window_s:", "galt_windows:"));
  EXPECT_NE(figures.find("figures.galt_windows: unknown key 'galt_windows' (did you mean 'galt_window_s'?)"),
            std::string::npos)
      << figures;
  // A key like none of them is named without a guess.
  EXPECT_NE(ErrorOf(std::string(kValid) + "colour: red\n").find("colour: unknown key 'colour'; known keys: "),
            std::string::npos);
}

// A label equal to another policy's perturbed label ("expert" under runtime:move is
// "expert.runtime.move") gives two cells one id: such a sweep could never finish.
TEST(SweepSpec, ALabelEqualToAPerturbedLabelIsRefusedNamingBoth) {
  const auto relabelled = [](const std::string& label) {
    return Replace(Replace(kLabelled, "label: still", "label: " + label), "[still, recipe]", "[expert-b, recipe]");
  };
  const std::string perturbed = "perturbations: [none, runtime:move]\n";
  const std::string error = ErrorOf(relabelled("expert-a.runtime.move") + perturbed);
  EXPECT_NE(error.find("policies[2].label: 'expert-a.runtime.move' names both policy 'expert-a' under runtime:move "
                       "and policy 'expert-a.runtime.move'"),
            std::string::npos)
      << error;
  const std::string group = ErrorOf(relabelled("recipe.runtime.move") + perturbed);
  EXPECT_NE(group.find("names both the seed group 'recipe' of policy 'expert-a' under runtime:move"), std::string::npos)
      << group;
  // Without the perturbation the same labels are distinct.
  EXPECT_EQ(Parse(relabelled("expert-a.runtime.move")).policies.size(), 3U);
}

// One combination of levels written in two orders is one scene: listed twice, it would run twice.
TEST(SweepSpec, ACombinationInAnotherOrderIsRefused) {
  const std::string error = ErrorOf(std::string(kValid) +
                                    "perturbations: [none, camera:fov-wide+sensor:noise-low, "
                                    "sensor:noise-low+camera:fov-wide]\n");
  EXPECT_NE(error.find("perturbations[2]: sensor:noise-low+camera:fov-wide is camera:fov-wide+sensor:noise-low "
                       "(perturbations[1]) in another order"),
            std::string::npos)
      << error;
}

// A cells: filter that allows none of the sweep's cells would leave its policy out without a word.
TEST(SweepSpec, ACellFilterThatSelectsNothingIsRefused) {
  const std::string robots = ErrorOf(Replace(kLabelled, "robots: [gr1t2, reachy2]", "robots: [gr1t2]"));
  EXPECT_NE(robots.find("policies[2].cells: selects no cell of the sweep: none of its robots (reachy2) is among the "
                        "sweep's (gr1t2)"),
            std::string::npos)
      << robots;
  const std::string tasks = ErrorOf(Replace(kLabelled, "cells: {robots: [reachy2],", "cells: {tasks: [peeking-box],"));
  EXPECT_NE(tasks.find("none of its tasks (peeking-box) is among the sweep's (clutter-pick-cube, wait-then-act)"),
            std::string::npos)
      << tasks;
  const std::string single =
      ErrorOf(Replace(kValid, "  name: expert", "  name: expert\n  cells: {cameras: [head-only]}"));
  EXPECT_NE(single.find("policy.cells: selects no cell of the sweep: none of its cameras (head-only)"),
            std::string::npos)
      << single;
}

// Every shard must get a cell: N is at most the sweep's cells.
TEST(SweepSpec, AShardCountAboveTheCellsIsRefused) {
  EXPECT_NO_THROW(RequireShardHoldsCells(ParseShard("3/4"), 4));
  for (const char* text : {"0/1000000", "0/5"}) {
    try {
      RequireShardHoldsCells(ParseShard(text), 4);
      ADD_FAILURE() << text << " was accepted for 4 cells";
    } catch (const output::SettingError& error) {
      EXPECT_EQ(error.key(), "shard");
      EXPECT_NE(error.problem().find(std::string("'") + text + "' splits the sweep's 4 cells into"), std::string::npos)
          << error.what();
      EXPECT_NE(error.problem().find("N must be 1 to 4"), std::string::npos) << error.what();
    }
  }
}

}  // namespace
}  // namespace tavis::batch::sweep

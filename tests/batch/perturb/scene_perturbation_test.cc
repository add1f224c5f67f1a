// The episode perturbation axes (docs/perturbations.md): distractors, language and runtime. Each
// changes what it claims (the extra objects exist where the rule puts them and are seen; the prompt
// is a paraphrase from the level's list; the target moves by the stated distance at the first tick
// a hand comes near, once, and the expert then goes for its new place) and keeps the base scene:
// the task's objects start where they start in the base cell, and what the axis does not touch is
// the base cell's.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "batch/cell/cell_record_stream.h"
#include "batch/cell/evaluation_cell.h"
#include "batch/perturb/perturbation_catalog.h"
#include "batch/scene_render.h"
#include "batch/vec_env.h"
#include "configs/yaml_reader.h"
#include "kinematics/forward_kinematics.h"
#include "kinematics/robot_buffers.h"
#include "scenarios/expert/pick_expert.h"
#include "scenarios/registry.h"
#include "tests/support/robot_loading.h"

namespace tavis::batch::perturb {
namespace {

using cell::CellResult;
using cell::EpisodeRecord;
using cell::EvaluationCellConfig;
using cell::RunEvaluationCell;

constexpr uint64_t kSeed = 11;

// A VecEnv of `slots` slots for the task on GR1T2 (or `robot`) under `choices`.
std::unique_ptr<VecEnv> MakeEnv(const std::string& task, const std::vector<std::string>& choices, int slots = 1,
                                const std::string& robot = "gr1t2") {
  const scenarios::ScenarioDef& scenario = scenarios::FindScenario(task);
  engine::WorldModel model = BuildWorldModel(tavis::testing::LoadRobot(robot), scenario);
  ApplyPerturbations(TAVIS_CONFIG_DIR, choices, kSeed, &model);
  return std::make_unique<VecEnv>(std::move(model), scenario, scenarios::Split::kId, slots, kSeed);
}

std::vector<double> PoseOf(const VecEnv& env, int slot, int object) {
  const double* pose = env.state().object_pose_row(slot, object);
  return {pose, pose + engine::kObjectPoseSize};
}

std::vector<int> EnabledDistractors(const VecEnv& env, int slot) {
  std::vector<int> enabled;
  for (int object = env.model().num_task_objects(); object < env.model().num_objects(); ++object) {
    if (env.state().object_enabled_at(slot, object)) enabled.push_back(object);
  }
  return enabled;
}

// True if the object's collision box, seen from above, lies inside the zone (its eight corners).
bool StandsInZone(const VecEnv& env, int slot, int object, const scenarios::SupportZone& zone) {
  const Vec3 half = BoundingHalfSize(env.model().objects[static_cast<std::size_t>(object)].shape);
  const RigidTransform X = MakeTransform(env.state().ObjectPosition(slot, object),
                                         env.state().ObjectOrientation(slot, object).toRotationMatrix());
  const Mat3 R_zone = Eigen::AngleAxisd(zone.yaw, Vec3::UnitZ()).toRotationMatrix();
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 sign((corner & 1) ? 1.0 : -1.0, (corner & 2) ? 1.0 : -1.0, (corner & 4) ? 1.0 : -1.0);
    const Vec3 local = R_zone.transpose() * (X * sign.cwiseProduct(half) - zone.centre);
    if (std::abs(local.x()) > zone.half_x + 1e-9 || std::abs(local.y()) > zone.half_y + 1e-9) return false;
  }
  return true;
}

// A config dir of its own holding `axis`'s level file with `text`.
std::string AxisConfigDir(const std::string& axis, const std::string& text) {
  static int files = 0;
  const std::filesystem::path dir =
      std::filesystem::path(::testing::TempDir()) / ("tavis_episode_axis_" + std::to_string(++files));
  std::filesystem::create_directories(dir / "perturbations");
  std::ofstream(dir / "perturbations" / (axis + ".yaml")) << text;
  return dir.string();
}

// The error reading `axis`'s level file with `text` gives ("" if none).
std::string AxisFileError(const std::string& axis, const std::string& text) {
  try {
    LoadPerturbationAxis(AxisConfigDir(axis, text), axis);
  } catch (const configs::ConfigError& error) {
    return error.what();
  }
  return "";
}

TEST(EpisodeAxes, BadLevelFilesAreRefusedNamingFileKeyAndValue) {
  const std::string mug =
      "objects:\n  - {name: mug, shape: cylinder, size_m: [0.03, 0.03, 0.09], mass_kg: 0.1, rgb: [0.3, 0.1, 0.5]}\n";
  struct Case {
    std::string axis, text;
    std::vector<std::string> named;  // what the message must contain
  };
  const std::vector<Case> cases = {
      {"distractors",
       "axis: distractors\n" + mug + "levels:\n  - {name: a, description: x, count: 2}\n",
       {"distractors.yaml", "levels[0].count", "1 to 1", "2"}},
      {"distractors",
       "axis: distractors\nobjects:\n  - {name: cone, shape: cone, size_m: [0.03, 0.03, 0.09], mass_kg: 0.1, rgb: [0, "
       "0, 0]}\n"
       "levels:\n  - {name: a, description: x, count: 1}\n",
       {"objects[0].shape", "cone"}},
      {"distractors",
       "axis: distractors\nobjects:\n  - {name: mug, shape: cylinder, size_m: [0.03, 0.04, 0.09], mass_kg: 0.1, rgb: "
       "[0, 0, 0]}\n"
       "levels:\n  - {name: a, description: x, count: 1}\n",
       {"objects[0].size_m", "radius"}},
      {"distractors", "axis: distractors\n" + mug + "levels:\n  - {name: a, description: x}\n", {"count"}},
      {"distractors",
       "axis: distractors\n" + mug + "levels:\n  - {name: a, description: x, count: 1, colour: red}\n",
       {"levels[0].colour"}},
      {"runtime",
       "axis: runtime\nlevels:\n  - {name: a, description: x, trigger_m: 0.09, distance_m: 0}\n",
       {"runtime.yaml", "levels[0].distance_m", "0"}},
      {"runtime", "axis: runtime\nlevels:\n  - {name: a, description: x, distance_m: 0.03}\n", {"trigger_m"}},
      {"language",
       "axis: language\nlevels:\n  - {name: a, description: x, prompts: {clutter-pick-cube: [Lift.]}}\n",
       {"language.yaml", "prompts", "clutter-pick-lift"}},
  };
  for (const Case& c : cases) {
    const std::string error = AxisFileError(c.axis, c.text);
    SCOPED_TRACE(c.text);
    ASSERT_FALSE(error.empty());
    for (const std::string& part : c.named) EXPECT_NE(error.find(part), std::string::npos) << error;
  }
  // Every task named, but one paraphrase with a placeholder other than {object}, one naming the
  // target without object names, and a task the registry does not know.
  std::string prompts;
  for (const scenarios::ScenarioDef& scenario : scenarios::AllScenarios())
    prompts += "      " + scenario.name + ": [Go.]\n";
  const std::string head = "axis: language\nlevels:\n  - name: a\n    description: x\n    prompts:\n";
  auto with = [&](const std::string& task, const std::string& line) {
    std::string text = prompts;
    const std::size_t at = text.find(task + ": [Go.]");
    return head + text.replace(at, task.size() + 7, task + ": " + line);
  };
  EXPECT_EQ(AxisFileError("language", head + prompts), "");
  const std::string braces = AxisFileError("language", with("peeking-box", "[\"Take the {thing}.\"]"));
  EXPECT_NE(braces.find("prompts.peeking-box[0]"), std::string::npos) << braces;
  EXPECT_NE(braces.find("{thing}"), std::string::npos) << braces;
  const std::string names = AxisFileError("language", with("peeking-box", "[\"Take the {object}.\"]"));
  EXPECT_NE(names.find("object_names"), std::string::npos) << names;
  const std::string unknown = AxisFileError("language", head + prompts + "      stack-blocks: [Go.]\n");
  EXPECT_NE(unknown.find("stack-blocks"), std::string::npos) << unknown;
}

// A task's paraphrases live with the task (ScenarioDef::paraphrases): a level that gives a task
// none of its own takes the task's for the level's name, one that gives some takes those, and a
// level that no task declares paraphrases for must give every task its own.
TEST(LanguageAxis, ALevelFallsBackToEachTasksOwnParaphrasesForItsName) {
  const std::string text =
      "axis: language\n"
      "object_names: {soup_can: a, meat_can: b, tuna_fish_can: c, gelatin_box: d, pudding_box: e, red_cube: f}\n"
      "levels:\n"
      "  - {name: paraphrase-terse, description: x}\n"
      "  - {name: paraphrase, description: y, prompts: {peeking-box: [Open the box.]}}\n";
  const std::vector<PerturbationLevel> levels = LoadPerturbationAxis(AxisConfigDir("language", text), "language");
  ASSERT_EQ(levels.size(), 2u);
  for (const scenarios::ScenarioDef& scenario : scenarios::AllScenarios()) {
    SCOPED_TRACE(scenario.name);
    const auto declared = [&](const std::string& level) {
      for (const scenarios::LevelParaphrases& own : scenario.paraphrases) {
        if (own.level == level) return own.texts;
      }
      return std::vector<std::string>();
    };
    ASSERT_FALSE(declared("paraphrase-terse").empty()) << "every task declares its own";
    EXPECT_EQ(levels[0].episode_effect.language.paraphrases.at(scenario.name), declared("paraphrase-terse"));
    const std::vector<std::string> given =
        scenario.name == "peeking-box" ? std::vector<std::string>{"Open the box."} : declared("paraphrase");
    EXPECT_EQ(levels[1].episode_effect.language.paraphrases.at(scenario.name), given);
    EXPECT_EQ(levels[1].settings.at("prompts").at(scenario.name), nlohmann::ordered_json(given))
        << "the cell records the paraphrases its level used";
  }
  const std::string none = AxisFileError("language", "axis: language\nlevels:\n  - {name: mumbled, description: x}\n");
  for (const char* part : {"language.yaml", "prompts.clutter-pick-lift", "level 'mumbled'"})
    EXPECT_NE(none.find(part), std::string::npos) << none;
}

TEST(DistractorsAxis, EveryTaskKeepsItsBaseSceneAndStandsTheDrawnObjectsInItsZones) {
  for (const scenarios::ScenarioDef& scenario : scenarios::AllScenarios()) {
    SCOPED_TRACE(scenario.name);
    const std::unique_ptr<VecEnv> base = MakeEnv(scenario.name, {});
    const std::unique_ptr<VecEnv> perturbed = MakeEnv(scenario.name, {"distractors:two"});
    const engine::WorldModel& model = perturbed->model();
    ASSERT_EQ(model.num_task_objects(), base->model().num_objects());
    ASSERT_EQ(model.num_objects(), base->model().num_objects() + 4) << "one object per declared kind";
    for (int64_t episode = 0; episode < 3; ++episode) {
      SCOPED_TRACE(episode);
      base->ResetEnv(0, episode);
      perturbed->ResetEnv(0, episode);
      for (int object = 0; object < model.num_task_objects(); ++object) {
        EXPECT_EQ(PoseOf(*perturbed, 0, object), PoseOf(*base, 0, object)) << model.objects[object].name;
        EXPECT_EQ(perturbed->state().object_enabled_at(0, object), base->state().object_enabled_at(0, object));
      }
      EXPECT_EQ(perturbed->state().task[0].target, base->state().task[0].target);
      const std::vector<int> distractors = EnabledDistractors(*perturbed, 0);
      ASSERT_EQ(distractors.size(), 2u) << "every drawn object finds a place";
      const std::vector<scenarios::SupportZone> zones = scenario.distractor_zones(perturbed->state(), 0);
      for (const int object : distractors) {
        const std::string& name = model.objects[static_cast<std::size_t>(object)].name;
        bool in_a_zone = false;
        for (const scenarios::SupportZone& zone : zones) {
          const bool inside = StandsInZone(*perturbed, 0, object, zone);
          const double above = perturbed->state().ObjectPosition(0, object).z() - zone.centre.z() -
                               BoundingHalfSize(model.objects[static_cast<std::size_t>(object)].shape).z();
          in_a_zone = in_a_zone || (inside && above >= 0.0 && above < 0.005);
        }
        EXPECT_TRUE(in_a_zone) << name << " stands on a zone's surface, wholly inside it";
        const Vec3 apart = perturbed->state().ObjectPosition(0, object) -
                           perturbed->state().ObjectPosition(0, perturbed->state().target(0));
        EXPECT_GT(apart.norm(), 0.08) << name << " is not on or against the target";
        const float* rgb = perturbed->state().object_rgb_row(0, object);
        EXPECT_GE(rgb[0], 0.0f) << name << " has its kind's colour";
      }
    }
  }
}

TEST(DistractorsAxis, AnEpisodesDistractorsDependOnlyOnSeedAndEpisode) {
  const std::unique_ptr<VecEnv> one = MakeEnv("clutter-pick-cube", {"distractors:one"}, 1);
  const std::unique_ptr<VecEnv> three = MakeEnv("clutter-pick-cube", {"distractors:one"}, 3);
  std::set<std::vector<double>> places;
  for (int64_t episode = 0; episode < 6; ++episode) {
    one->ResetEnv(0, episode);
    three->ResetEnv(static_cast<int>(episode % 3), episode);
    const std::vector<int> here = EnabledDistractors(*one, 0);
    ASSERT_EQ(here.size(), 1u);
    EXPECT_EQ(EnabledDistractors(*three, static_cast<int>(episode % 3)), here);
    EXPECT_EQ(PoseOf(*three, static_cast<int>(episode % 3), here[0]), PoseOf(*one, 0, here[0]));
    places.insert(PoseOf(*one, 0, here[0]));
  }
  EXPECT_EQ(places.size(), 6u) << "each episode draws its own place";
}

TEST(DistractorsAxis, TheFixedCameraSeesThemAndTheTaskObjectsAsBefore) {
  // Object ids tell which pixels show a distractor: those change colour; pixels of the task's
  // objects that no distractor hides or shades keep theirs.
  CameraSettings settings;
  settings.cameras = {"fixed"};
  settings.width = 128;
  settings.height = 96;
  settings.with_object_id = true;
  std::array<std::vector<uint8_t>, 2> rgb;
  std::array<std::vector<int32_t>, 2> ids;
  int first_distractor = 0;
  for (int i = 0; i < 2; ++i) {
    const std::unique_ptr<VecEnv> env = MakeEnv(
        "clutter-pick-cube", i == 0 ? std::vector<std::string>{} : std::vector<std::string>{"distractors:four"});
    first_distractor = env->model().num_task_objects();
    env->EnableCameras(settings);
    env->ResetEnv(0, 0);
    env->RenderPolicyTick();
    const uint8_t* image = env->images()->rgb(0, 0);
    const int32_t* id = env->images()->object_id(0, 0);
    rgb[i].assign(image, image + 3 * settings.width * settings.height);
    ids[i].assign(id, id + settings.width * settings.height);
  }
  int distractor_pixels = 0, changed = 0;
  for (std::size_t p = 0; p < ids[1].size(); ++p) {
    if (ids[1][p] < first_distractor) continue;
    ++distractor_pixels;
    changed += rgb[1][3 * p] != rgb[0][3 * p] || rgb[1][3 * p + 1] != rgb[0][3 * p + 1] ||
               rgb[1][3 * p + 2] != rgb[0][3 * p + 2];
  }
  EXPECT_GT(distractor_pixels, 40) << "the four distractors are in view";
  EXPECT_GT(changed, 0.9 * distractor_pixels);
  int task_pixels = 0;
  for (std::size_t p = 0; p < ids[0].size(); ++p) task_pixels += ids[0][p] >= 0 && ids[1][p] == ids[0][p];
  EXPECT_GT(task_pixels, 100) << "the task's objects are still seen where they were";
}

// Two episodes of the scripted expert on the task's id split, on two slots.
EvaluationCellConfig ExpertCell(const std::string& task, const std::string& robot, uint64_t seed,
                                std::vector<std::string> perturbations = {}) {
  EvaluationCellConfig config;
  config.task = task;
  config.robot = robot;
  config.policy = "expert";
  config.episodes = 2;
  config.envs = 2;
  config.seed = seed;
  config.config_dir = TAVIS_CONFIG_DIR;
  config.perturbations = std::move(perturbations);
  return config;
}

TEST(DistractorsAxis, TheExpertStillPicksWithFourObjectsBesideTheTask) {
  const EvaluationCellConfig config = ExpertCell("clutter-pick-cube", "gr1t2", 3, {"distractors:four"});
  const CellResult result = RunEvaluationCell(config);
  EXPECT_EQ(result.successes, 2);
}

TEST(LanguageAxis, EachEpisodeGetsAParaphraseFromItsTasksListAlwaysTheSame) {
  for (const PerturbationLevel& level : LoadPerturbationAxis(TAVIS_CONFIG_DIR, "language")) {
    SCOPED_TRACE(level.name);
    const engine::LanguageSettings& language = level.episode_effect.language;
    for (const scenarios::ScenarioDef& scenario : scenarios::AllScenarios()) {
      SCOPED_TRACE(scenario.name);
      const std::unique_ptr<VecEnv> base = MakeEnv(scenario.name, {});
      const std::unique_ptr<VecEnv> paraphrased = MakeEnv(scenario.name, {"language:" + level.name});
      const std::unique_ptr<VecEnv> other_slots = MakeEnv(scenario.name, {"language:" + level.name}, 2);
      std::set<std::string> used;
      for (int64_t episode = 0; episode < 8; ++episode) {
        base->ResetEnv(0, episode);
        paraphrased->ResetEnv(0, episode);
        other_slots->ResetEnv(1, episode);
        const std::string prompt = paraphrased->prompt(0);
        EXPECT_EQ(other_slots->prompt(1), prompt) << "episode " << episode << " draws the same paraphrase";
        EXPECT_NE(prompt, base->prompt(0)) << "a paraphrase is not the demonstrations' prompt";
        EXPECT_EQ(PoseOf(*paraphrased, 0, paraphrased->state().target(0)), PoseOf(*base, 0, base->state().target(0)));
        // The prompt is one of the list, with {object} the target's name in the level.
        const std::string target = paraphrased->model().objects[paraphrased->state().target(0)].name;
        bool listed = false;
        for (std::string text : language.paraphrases.at(scenario.name)) {
          const std::size_t at = text.find("{object}");
          if (at != std::string::npos) text.replace(at, 8, language.object_names.at(target));
          listed = listed || text == prompt;
        }
        EXPECT_TRUE(listed) << prompt;
        used.insert(prompt);
      }
      if (language.paraphrases.at(scenario.name).size() > 1) {
        EXPECT_GT(used.size(), 1u) << "eight episodes draw more than one of several paraphrases";
      }
    }
  }
}

TEST(LanguageAxis, OnlyThePromptDiffersFromTheBaseCell) {
  EvaluationCellConfig base = ExpertCell("clutter-pick-lift", "reachy2", 4);
  base.keep_actions = true;
  const CellResult reference = RunEvaluationCell(base);
  EvaluationCellConfig perturbed = base;
  perturbed.perturbations = {"language:paraphrase-synonyms"};
  const CellResult result = RunEvaluationCell(perturbed);
  ASSERT_EQ(result.episodes.size(), reference.episodes.size());
  for (std::size_t i = 0; i < result.episodes.size(); ++i) {
    const EpisodeRecord& a = result.episodes[i];
    const EpisodeRecord& b = reference.episodes[i];
    EXPECT_NE(a.prompt, b.prompt);
    EXPECT_EQ(a.success, b.success);
    EXPECT_EQ(a.end, b.end);
    EXPECT_EQ(a.length_control_ticks, b.length_control_ticks);
    EXPECT_EQ(a.target_object, b.target_object);
    EXPECT_EQ(a.actions, b.actions) << "episode " << i;
    EXPECT_FALSE(a.target_move_tick.has_value());
  }
}

// The runtime axis, followed tick by tick with the task's scripted expert.
struct MoveTrace {
  int move_tick = -1;   // TaskVars::target_move_tick at the end
  int first_near = -1;  // first tick a tool centre point was within the trigger of the target's centre
  Vec3 before, after;   // the target's centre on the tick before the move and on the move's tick
  int jumps = 0;        // ticks on which the target's centre jumped more than 2 cm sideways
  Vec3 grasp_command;   // the closing hand's commanded pad centre (world) at the first close after the move
  bool closed_after_move = false;
  int replans = 0;
  bool success = false;
};

MoveTrace FollowMove(const std::string& task, const std::string& level, int64_t episode, const std::string& robot) {
  const std::unique_ptr<VecEnv> env = MakeEnv(task, {"runtime:" + level}, 1, robot);
  const engine::WorldModel& model = env->model();
  const double trigger = model.episode_perturbation.target_move.trigger_m;
  std::unique_ptr<scenarios::Expert> expert =
      env->scenario().make_expert(model, 1, scenarios::expert::ExpertMode::kGazeFirst);
  env->ResetEnv(0, episode);
  expert->Reset(model, env->state(), 0);
  MoveTrace trace;
  LinkPoses X_BL;
  std::vector<kinematics::Action> actions(1);
  Vec3 last = env->state().ObjectPosition(0, env->state().target(0));
  while (env->state().running(0)) {
    expert->Act(model, env->state(), 0, actions[0]);
    env->Step(actions);
    const engine::BatchState& state = env->state();
    const Vec3 now = state.ObjectPosition(0, state.target(0));
    // Horizontally: the objects fall a few centimetres a tick onto the table after the reset.
    if (std::hypot(now.x() - last.x(), now.y() - last.y()) > 0.02) {
      ++trace.jumps;
      if (trace.move_tick < 0) {
        trace.before = last;
        trace.after = now;
      }
    }
    if (trace.move_tick < 0) trace.move_tick = state.task[0].target_move_tick;
    // Measured to where the target was before this tick's move, as the trigger sees it.
    const Vec3 measured_from = state.task[0].target_move_tick == state.control_step[0] ? last : now;
    for (const kinematics::Side side : kinematics::kSides) {
      const Vec3 tcp = kinematics::ToolCentrePointWorld(model.robot, state.q_row(0), side, X_BL.data());
      if (trace.first_near < 0 && (tcp - measured_from).norm() <= trigger) trace.first_near = state.control_step[0];
      const int gripper = kinematics::action::kGripper[kinematics::Index(side)];
      if (trace.move_tick >= 0 && !trace.closed_after_move && actions[0][gripper] > 0.0) {
        trace.closed_after_move = true;
        const int p = kinematics::action::kArmPosition[kinematics::Index(side)];
        const int r = kinematics::action::kArmQuaternion[kinematics::Index(side)];
        const RigidTransform X_canonical_ik = MakeTransform(
            Vec3(actions[0][p], actions[0][p + 1], actions[0][p + 2]),
            Quat(actions[0][r], actions[0][r + 1], actions[0][r + 2], actions[0][r + 3]).toRotationMatrix());
        trace.grasp_command =
            model.robot.CanonicalToBase(X_canonical_ik * model.robot.gripper.pad_center) + model.robot.root_world;
      }
    }
    last = now;
  }
  trace.replans = dynamic_cast<const scenarios::expert::PickExpert&>(*expert).replans(0);
  trace.success = env->state().end[0] == engine::EpisodeEnd::kSuccess;
  return trace;
}

TEST(RuntimeAxis, TheTargetMovesOnceByTheStatedDistanceAtTheFirstTickAHandComesNear) {
  for (const auto& [level, distance] : {std::pair<std::string, double>{"nudge", 0.03}, {"move", 0.08}}) {
    SCOPED_TRACE(level);
    // The first of a few episodes whose target had a free place to go (most have).
    MoveTrace trace;
    for (int64_t episode = 0; episode < 4 && trace.move_tick < 0; ++episode)
      trace = FollowMove("clutter-pick-cube", level, episode, "gr1t2");
    ASSERT_GE(trace.move_tick, 0) << "the hand came near and the target was moved";
    EXPECT_EQ(trace.move_tick, trace.first_near);
    const Vec3 shift = trace.after - trace.before;
    EXPECT_NEAR(std::hypot(shift.x(), shift.y()), distance, 0.003) << "horizontally, by the stated distance";
    EXPECT_NEAR(shift.z(), 0.0, 0.003);
    EXPECT_EQ(trace.jumps, 1) << "once";
    // The expert noticed it and went for the new place: its next grasp closes there.
    EXPECT_EQ(trace.replans, 1);
    ASSERT_TRUE(trace.closed_after_move);
    const Vec3 to_new = trace.grasp_command - trace.after;
    const Vec3 to_old = trace.grasp_command - trace.before;
    EXPECT_LT(std::hypot(to_new.x(), to_new.y()), 0.02);
    EXPECT_GT(std::hypot(to_old.x(), to_old.y()), distance - 0.02);
    EXPECT_TRUE(trace.success);
  }
}

TEST(RuntimeAxis, ATargetWithNoFreePlaceStaysWhereItIs) {
  // The task's zone for the moved target left empty: the hand comes near once, nothing moves, and
  // the expert picks the target where it always was.
  scenarios::ScenarioDef nowhere = scenarios::FindScenario("clutter-pick-cube");
  nowhere.target_zones = [](const engine::BatchState&, int) { return std::vector<scenarios::SupportZone>{}; };
  engine::WorldModel model = BuildWorldModel(tavis::testing::LoadRobot("gr1t2"), nowhere);
  ApplyPerturbations(TAVIS_CONFIG_DIR, {"runtime:move"}, kSeed, &model);
  VecEnv env(std::move(model), nowhere, scenarios::Split::kId, 1, kSeed);
  std::unique_ptr<scenarios::Expert> expert =
      nowhere.make_expert(env.model(), 1, scenarios::expert::ExpertMode::kGazeFirst);
  env.ResetEnv(0, 0);
  expert->Reset(env.model(), env.state(), 0);
  std::vector<kinematics::Action> actions(1);
  while (env.state().running(0)) {
    expert->Act(env.model(), env.state(), 0, actions[0]);
    env.Step(actions);
  }
  EXPECT_TRUE(env.state().task[0].target_move_tried) << "a hand came near";
  EXPECT_EQ(env.state().task[0].target_move_tick, -1);
  EXPECT_EQ(dynamic_cast<const scenarios::expert::PickExpert&>(*expert).replans(0), 0);
  EXPECT_EQ(env.state().end[0], engine::EpisodeEnd::kSuccess);
}

TEST(RuntimeAxis, ACellRecordsTheMoveAndTheBaseCellHasNone) {
  const EvaluationCellConfig base = ExpertCell("clutter-pick-lift", "reachy2", 2);
  for (const EpisodeRecord& record : RunEvaluationCell(base).episodes) EXPECT_FALSE(record.target_move_tick);
  EvaluationCellConfig perturbed = base;
  perturbed.perturbations = {"runtime:move", "distractors:one", "language:paraphrase", "camera:fov-wide"};
  const CellResult result = RunEvaluationCell(perturbed);
  for (const EpisodeRecord& record : result.episodes) {
    ASSERT_TRUE(record.target_move_tick.has_value());
    EXPECT_GT(*record.target_move_tick, 0) << "episode " << record.episode;
    EXPECT_TRUE(record.success) << "episode " << record.episode;
  }
  const nlohmann::json settings = CellSettingsJson(perturbed);
  ASSERT_EQ(settings["perturbations"].size(), 4u);
  EXPECT_EQ(settings["perturbations"][0]["settings"]["distance_m"], 0.08);
  EXPECT_EQ(settings["perturbations"][1]["settings"]["objects"][0]["name"], "mug");
  EXPECT_EQ(settings["perturbations"][2]["settings"]["prompts"]["clutter-pick-lift"].size(), 1u);
}

}  // namespace
}  // namespace tavis::batch::perturb

// The perturbation axes (batch/perturb/perturbation_catalog.h, batch/perturb/perturbed_view.h): the shipped level
// files load; a bad file is refused naming the file, the key and the value; every axis changes the
// pixels it claims to and only those; the physics, the scene and the expert's motion are those of
// the base scene; and the default (no perturbation) leaves every image untouched.
#include "batch/perturb/perturbation_catalog.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "batch/cell/cell_record_stream.h"
#include "batch/cell/evaluation_cell.h"
#include "batch/perturb/perturbed_view.h"
#include "batch/report/perturbation_pairs.h"
#include "batch/scene_render.h"
#include "batch/vec_env.h"
#include "configs/robot_config.h"
#include "configs/yaml_reader.h"
#include "scenarios/registry.h"
#include "tests/batch/rendered_expert_cell.h"

namespace tavis::batch::perturb {
namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 96;
constexpr int kHeight = 72;

// The four cameras of episode `episode` (seed 5) at its reset, under `choices`.
struct Views {
  std::vector<std::vector<uint8_t>> rgb;  // [camera in SceneCameraNames() order]
  std::vector<double> object_poses;       // every object's pose at the reset
};

Views RenderReset(const std::vector<std::string>& choices, int64_t episode = 0,
                  const std::string& task = "clutter-pick-cube") {
  const scenarios::ScenarioDef& scenario = scenarios::FindScenario(task);
  const kinematics::RobotModel robot = configs::LoadRobotModel(configs::RobotConfigPath(TAVIS_CONFIG_DIR, "gr1t2"));
  engine::WorldModel model = BuildWorldModel(robot, scenario);
  ApplyPerturbations(TAVIS_CONFIG_DIR, choices, 5, &model);
  VecEnv vec_env(std::move(model), scenario, scenarios::Split::kId, 1, 5);
  CameraSettings settings;
  settings.cameras = SceneCameraNames();
  settings.width = kWidth;
  settings.height = kHeight;
  vec_env.EnableCameras(settings);  // the task's black cameras start blocked
  vec_env.Reset({{0, episode}});
  vec_env.RenderPolicyTick();
  Views views;
  const render::ImageBatch& images = *vec_env.images();
  for (int c = 0; c < images.n_cameras(); ++c) {
    const uint8_t* rgb = images.rgb(0, c);
    views.rgb.emplace_back(rgb, rgb + 3 * kWidth * kHeight);
  }
  for (int object = 0; object < vec_env.model().num_objects(); ++object) {
    const double* pose = vec_env.state().object_pose_row(0, object);
    views.object_poses.insert(views.object_poses.end(), pose, pose + 7);
  }
  return views;
}

int CameraIndexOf(const std::string& name) {
  const std::vector<std::string>& names = SceneCameraNames();
  return static_cast<int>(std::find(names.begin(), names.end(), name) - names.begin());
}

// Mean absolute difference per channel value between two images.
double MeanAbsDifference(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += std::abs(static_cast<int>(a[i]) - static_cast<int>(b[i]));
  return sum / static_cast<double>(a.size());
}

double ChannelMean(const std::vector<uint8_t>& rgb, int channel) {
  double sum = 0.0;
  for (std::size_t i = static_cast<std::size_t>(channel); i < rgb.size(); i += 3) sum += rgb[i];
  return sum / static_cast<double>(rgb.size() / 3);
}

// Sum of absolute differences between horizontal neighbours: what a blur lowers.
double Sharpness(const std::vector<uint8_t>& rgb) {
  double sum = 0.0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 1; x < kWidth; ++x) {
      for (int ch = 0; ch < 3; ++ch) {
        sum += std::abs(rgb[(static_cast<std::size_t>(y) * kWidth + x) * 3 + ch] -
                        rgb[(static_cast<std::size_t>(y) * kWidth + x - 1) * 3 + ch]);
      }
    }
  }
  return sum;
}

// A config dir holding one perturbation file with `text`, for the validation tests.
std::string ConfigDirWith(const std::string& axis, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() /
                       ("tavis_perturbation_test_" + axis + "_" + std::to_string(std::hash<std::string>()(text)));
  fs::create_directories(dir / "perturbations");
  std::ofstream(dir / "perturbations" / (axis + ".yaml")) << text;
  return dir.string();
}

std::string LoadError(const std::string& axis, const std::string& text) {
  try {
    LoadPerturbationAxis(ConfigDirWith(axis, text), axis);
  } catch (const configs::ConfigError& error) {
    return error.what();
  }
  return "";
}

TEST(PerturbationCatalog, EveryShippedAxisLoadsWithLevelsThatChangeSomething) {
  for (const std::string& axis : PerturbationAxisNames()) {
    SCOPED_TRACE(axis);
    const std::vector<PerturbationLevel> levels = LoadPerturbationAxis(TAVIS_CONFIG_DIR, axis);
    ASSERT_GE(levels.size(), 2u);
    for (const PerturbationLevel& level : levels) {
      EXPECT_EQ(level.axis, axis);
      EXPECT_FALSE(level.description.empty()) << level.name;
      const engine::RenderPerturbation& e = level.effect;
      const engine::EpisodePerturbation& episodes = level.episode_effect;
      EXPECT_TRUE(e.moves_cameras() || e.changes_lighting() || e.changes_images() || e.changes_surfaces() ||
                  episodes.adds_distractors() || episodes.paraphrases_prompt() || episodes.moves_target())
          << level.name;
    }
  }
}

TEST(PerturbationCatalog, BadFilesAreRefusedNamingFileKeyAndValue) {
  const std::string unknown_key =
      LoadError("sensor", "axis: sensor\nlevels:\n  - name: a\n    description: x\n    noise_sigma: 3\n");
  EXPECT_NE(unknown_key.find("sensor.yaml"), std::string::npos) << unknown_key;
  EXPECT_NE(unknown_key.find("noise_sigma"), std::string::npos) << unknown_key;

  const std::string out_of_range =
      LoadError("sensor", "axis: sensor\nlevels:\n  - name: a\n    description: x\n    noise_stddev: 400\n");
  EXPECT_NE(out_of_range.find("noise_stddev"), std::string::npos) << out_of_range;
  EXPECT_NE(out_of_range.find("400"), std::string::npos) << out_of_range;

  const std::string wrong_axis =
      LoadError("camera", "axis: lighting\nlevels:\n  - name: a\n    description: x\n    head_fov_scale: 1.1\n");
  EXPECT_NE(wrong_axis.find("axis"), std::string::npos) << wrong_axis;
  EXPECT_NE(wrong_axis.find("lighting"), std::string::npos) << wrong_axis;

  const std::string twice = LoadError("sensor",
                                      "axis: sensor\nlevels:\n  - name: a\n    description: x\n    noise_stddev: 2\n  "
                                      "- name: a\n    description: y\n    noise_stddev: 3\n");
  EXPECT_NE(twice.find("twice"), std::string::npos) << twice;

  const std::string nothing = LoadError("sensor", "axis: sensor\nlevels:\n  - name: a\n    description: x\n");
  EXPECT_NE(nothing.find("base scene"), std::string::npos) << nothing;

  const std::string bad_name =
      LoadError("sensor", "axis: sensor\nlevels:\n  - name: A.b\n    description: x\n    noise_stddev: 2\n");
  EXPECT_NE(bad_name.find("A.b"), std::string::npos) << bad_name;

  // In range for the key, but no camera can have it: an angle of view of 2 x 66 degrees x 2.
  const std::string wide =
      LoadError("camera", "axis: camera\nlevels:\n  - name: a\n    description: x\n    fixed_fov_scale: 2.0\n");
  EXPECT_NE(wide.find("fixed_fov_scale"), std::string::npos) << wide;

  const std::string below =
      LoadError("lighting", "axis: lighting\nlevels:\n  - name: a\n    description: x\n    elevation_deg: -80\n");
  EXPECT_NE(below.find("elevation_deg"), std::string::npos) << below;

  const std::string top_key =
      LoadError("sensor", "axis: sensor\nseverity: 3\nlevels:\n  - name: a\n    description: x\n    noise_stddev: 2\n");
  EXPECT_NE(top_key.find("severity"), std::string::npos) << top_key;
}

TEST(PerturbationCatalog, ChoicesAreCheckedAgainstTheFiles) {
  auto error_of = [](const std::vector<std::string>& choices) {
    try {
      ResolvePerturbations(TAVIS_CONFIG_DIR, choices);
    } catch (const std::invalid_argument& error) {
      return std::string(error.what());
    }
    return std::string();
  };
  EXPECT_NE(error_of({"camera"}).find("AXIS:LEVEL"), std::string::npos);
  EXPECT_NE(error_of({"weather:rain"}).find("'weather'"), std::string::npos);
  const std::string unknown_level = error_of({"camera:sideways"});
  EXPECT_NE(unknown_level.find("'sideways'"), std::string::npos) << unknown_level;
  EXPECT_NE(unknown_level.find("fov-wide"), std::string::npos) << "lists the known levels: " << unknown_level;
  EXPECT_NE(error_of({"sensor:noise-low", "sensor:blur-low"}).find("already chosen"), std::string::npos);
  EXPECT_EQ(ResolvePerturbations(TAVIS_CONFIG_DIR, {"sensor:noise-low", "camera:fov-wide"}).size(), 2u);
}

TEST(PerturbationCatalog, CellFilesRecordTheLevelsAndTheBaseCellIsAsBefore) {
  cell::EvaluationCellConfig config;
  config.config_dir = TAVIS_CONFIG_DIR;
  const nlohmann::json base = cell::CellSettingsJson(config);
  EXPECT_FALSE(base.contains("perturbations")) << "a base cell's cell.json keeps its old keys";
  config.perturbations = {"lighting:warm"};
  const nlohmann::json perturbed = cell::CellSettingsJson(config);
  ASSERT_TRUE(perturbed.contains("perturbations"));
  EXPECT_EQ(perturbed["perturbations"][0]["axis"], "lighting");
  EXPECT_EQ(perturbed["perturbations"][0]["level"], "warm");
  EXPECT_EQ(perturbed["perturbations"][0]["settings"]["colour_temperature_k"], 3000.0);
}

TEST(PerturbedView, TheDefaultChangesNothing) {
  const engine::RenderPerturbation none;
  EXPECT_FALSE(none.moves_cameras() || none.changes_lighting() || none.changes_images() || none.changes_surfaces());
  const render::CameraSpec head = render::HeadCameraSpec();
  EXPECT_EQ(PerturbedCameraSpec(head, none).focal_length_mm, head.focal_length_mm);
  EXPECT_TRUE(CameraMountOffset("head", none).isApprox(RigidTransform::Identity(), 0.0));
  const RigidTransform fixed = render::FixedCameraPose();
  EXPECT_TRUE(PerturbedFixedCameraPose(fixed, none).isApprox(fixed, 0.0));
  render::LightingSpec lighting;
  const render::LightingSpec before = lighting;
  PerturbLighting(none, &lighting);
  EXPECT_EQ(lighting.distant_direction, before.distant_direction);
  EXPECT_EQ(lighting.dome_rgb, before.dome_rgb);
  EXPECT_EQ(lighting.distant_intensity, before.distant_intensity);
  // Rendered: a model whose perturbation was reset to the default draws what a fresh model draws.
  const Views base = RenderReset({});
  const Views again = RenderReset({});
  EXPECT_EQ(base.rgb, again.rgb);
}

TEST(PerturbedView, FixedCameraYawPansAboutTheVerticalAndPitchTiltsItDown) {
  const RigidTransform X_WC = render::FixedCameraPose();
  const Vec3 forward = X_WC.linear().col(0);  // the optical axis (camera x)
  engine::RenderPerturbation pan;
  pan.fixed_rotation_deg = Vec3(0.0, 0.0, 30.0);
  const Vec3 panned = PerturbedFixedCameraPose(X_WC, pan).linear().col(0);
  EXPECT_NEAR(panned.z(), forward.z(), 1e-12) << "a pan keeps the downward angle";
  const double turned = std::atan2(panned.y(), panned.x()) - std::atan2(forward.y(), forward.x());
  EXPECT_NEAR(turned, 30.0 * M_PI / 180.0, 1e-9) << "positive yaw pans left";
  engine::RenderPerturbation tilt;
  tilt.fixed_rotation_deg = Vec3(0.0, 10.0, 0.0);
  const Vec3 tilted = PerturbedFixedCameraPose(X_WC, tilt).linear().col(0);
  EXPECT_NEAR(std::asin(-tilted.z()) - std::asin(-forward.z()), 10.0 * M_PI / 180.0, 1e-9)
      << "positive pitch looks further down";
  engine::RenderPerturbation move;
  move.fixed_offset_m = Vec3(0.0, 0.25, 0.1);
  EXPECT_TRUE(PerturbedFixedCameraPose(X_WC, move).translation().isApprox(X_WC.translation() + move.fixed_offset_m));
}

TEST(PerturbedView, BlackBodyTintIsWhiteAt6500KWarmBelowAndCoolAbove) {
  const Eigen::Vector3f white = BlackBodyTint(6500.0);
  EXPECT_NEAR(white.x(), 1.0f, 1e-5f);
  EXPECT_NEAR(white.z(), 1.0f, 1e-5f);
  const Eigen::Vector3f warm = BlackBodyTint(3000.0);
  EXPECT_GT(warm.x(), warm.y());
  EXPECT_GT(warm.y(), warm.z());
  const Eigen::Vector3f cool = BlackBodyTint(10000.0);
  EXPECT_LT(cool.x(), cool.z());
  EXPECT_THROW(BlackBodyTint(500.0), std::invalid_argument);
}

TEST(PerturbationAxes, CameraLevelsMoveOnlyTheirCamerasAndKeepTheScene) {
  const Views base = RenderReset({});
  const int head = CameraIndexOf("head");
  const int fixed = CameraIndexOf("fixed");
  const int left = CameraIndexOf("left_wrist");
  const int right = CameraIndexOf("right_wrist");
  struct Case {
    const char* level;
    bool head_changes;
    bool fixed_changes;
  };
  for (const Case& c : {Case{"head-mount-small", true, false}, Case{"head-mount-large", true, false},
                        Case{"fixed-view-small", false, true}, Case{"fixed-view-large", false, true},
                        Case{"fov-narrow", true, true}, Case{"fov-wide", true, true}}) {
    SCOPED_TRACE(c.level);
    const Views views = RenderReset({std::string("camera:") + c.level});
    EXPECT_EQ(views.object_poses, base.object_poses) << "the scene is the base scene's";
    EXPECT_EQ(views.rgb[static_cast<std::size_t>(head)] != base.rgb[static_cast<std::size_t>(head)], c.head_changes);
    EXPECT_EQ(views.rgb[static_cast<std::size_t>(fixed)] != base.rgb[static_cast<std::size_t>(fixed)], c.fixed_changes);
    if (c.head_changes) {
      EXPECT_GT(MeanAbsDifference(views.rgb[static_cast<std::size_t>(head)], base.rgb[static_cast<std::size_t>(head)]),
                1.0);
    }
    if (c.fixed_changes) {
      EXPECT_GT(
          MeanAbsDifference(views.rgb[static_cast<std::size_t>(fixed)], base.rgb[static_cast<std::size_t>(fixed)]),
          1.0);
    }
    EXPECT_EQ(views.rgb[static_cast<std::size_t>(left)], base.rgb[static_cast<std::size_t>(left)])
        << "wrist cameras stay";
    EXPECT_EQ(views.rgb[static_cast<std::size_t>(right)], base.rgb[static_cast<std::size_t>(right)])
        << "wrist cameras stay";
  }
}

TEST(PerturbationAxes, LightingLevelsChangeEveryViewAsDeclared) {
  const Views base = RenderReset({});
  const int fixed = CameraIndexOf("fixed");
  auto brightness = [](const std::vector<uint8_t>& rgb) {
    return ChannelMean(rgb, 0) + ChannelMean(rgb, 1) + ChannelMean(rgb, 2);
  };
  for (const char* level : {"dim", "bright", "low-side-sun", "warm", "cool"}) {
    SCOPED_TRACE(level);
    const Views views = RenderReset({std::string("lighting:") + level});
    EXPECT_EQ(views.object_poses, base.object_poses);
    for (std::size_t c = 0; c < views.rgb.size(); ++c) EXPECT_NE(views.rgb[c], base.rgb[c]) << SceneCameraNames()[c];
  }
  const std::vector<uint8_t>& base_fixed = base.rgb[static_cast<std::size_t>(fixed)];
  EXPECT_LT(brightness(RenderReset({"lighting:dim"}).rgb[static_cast<std::size_t>(fixed)]),
            brightness(base_fixed) - 30.0);
  EXPECT_GT(brightness(RenderReset({"lighting:bright"}).rgb[static_cast<std::size_t>(fixed)]),
            brightness(base_fixed) + 30.0);
  const std::vector<uint8_t> warm = RenderReset({"lighting:warm"}).rgb[static_cast<std::size_t>(fixed)];
  const std::vector<uint8_t> cool = RenderReset({"lighting:cool"}).rgb[static_cast<std::size_t>(fixed)];
  const double base_ratio = ChannelMean(base_fixed, 0) / ChannelMean(base_fixed, 2);
  EXPECT_GT(ChannelMean(warm, 0) / ChannelMean(warm, 2), base_ratio * 1.2) << "warm light is redder";
  EXPECT_LT(ChannelMean(cool, 0) / ChannelMean(cool, 2), base_ratio / 1.05) << "cool light is bluer";
}

TEST(PerturbationAxes, SensorNoiseHasItsDeclaredSpreadAndRepeatsPerEpisodeAndTick) {
  const Views base = RenderReset({});
  const Views noisy = RenderReset({"sensor:noise-high"});
  EXPECT_EQ(noisy.object_poses, base.object_poses);
  const int fixed = CameraIndexOf("fixed");
  const std::vector<uint8_t>& clean = base.rgb[static_cast<std::size_t>(fixed)];
  const std::vector<uint8_t>& dirty = noisy.rgb[static_cast<std::size_t>(fixed)];
  // cell::Spread of the difference over unclipped values: the declared 16 levels.
  double sum = 0.0, sum_sq = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < clean.size(); ++i) {
    if (clean[i] < 60 || clean[i] > 195) continue;
    const double d = static_cast<double>(dirty[i]) - clean[i];
    sum += d;
    sum_sq += d * d;
    ++n;
  }
  ASSERT_GT(n, 1000);
  const double mean = sum / n;
  const double stddev = std::sqrt(sum_sq / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 1.0);
  EXPECT_NEAR(stddev, 16.0, 1.5);
  for (std::size_t c = 0; c < base.rgb.size(); ++c) EXPECT_NE(noisy.rgb[c], base.rgb[c]) << SceneCameraNames()[c];
  EXPECT_EQ(RenderReset({"sensor:noise-high"}).rgb, noisy.rgb) << "the same episode and tick: the same noise";
  // Another episode draws other noise (compared as noise: each image minus its own base image).
  const Views other = RenderReset({"sensor:noise-high"}, 1);
  const Views other_base = RenderReset({}, 1);
  std::vector<int> noise_here, noise_there;
  for (std::size_t i = 0; i < clean.size(); ++i) {
    noise_here.push_back(dirty[i] - clean[i]);
    noise_there.push_back(other.rgb[static_cast<std::size_t>(fixed)][i] -
                          other_base.rgb[static_cast<std::size_t>(fixed)][i]);
  }
  EXPECT_NE(noise_here, noise_there);
}

TEST(PerturbationAxes, SensorBlurSoftensEdgesAndBlockedCamerasStayBlack) {
  const Views base = RenderReset({});
  const int fixed = CameraIndexOf("fixed");
  const double sharp = Sharpness(base.rgb[static_cast<std::size_t>(fixed)]);
  const double low = Sharpness(RenderReset({"sensor:blur-low"}).rgb[static_cast<std::size_t>(fixed)]);
  const double high = Sharpness(RenderReset({"sensor:blur-high"}).rgb[static_cast<std::size_t>(fixed)]);
  EXPECT_LT(low, 0.9 * sharp);
  EXPECT_LT(high, 0.8 * low);
  // blocked-clutter-pick-cube's head image is black, as a blocked camera: noise does not light it.
  const Views blocked = RenderReset({"sensor:noise-high"}, 0, "blocked-clutter-pick-cube");
  const std::vector<uint8_t>& head = blocked.rgb[static_cast<std::size_t>(CameraIndexOf("head"))];
  EXPECT_TRUE(std::all_of(head.begin(), head.end(), [](uint8_t v) { return v == 0; }));
}

TEST(PerturbationAxes, ViewAxesLeaveTheExpertsEpisodesExactlyAsInTheBaseCell) {
  const cell::EvaluationCellConfig base = testing::RenderedExpertCell("reachy2", 2, 7);
  const cell::CellResult reference = cell::RunEvaluationCell(base);
  for (const char* choice : {"camera:head-mount-large", "lighting:low-side-sun", "sensor:noise-high"}) {
    SCOPED_TRACE(choice);
    cell::EvaluationCellConfig perturbed = base;
    perturbed.perturbations = {choice};
    testing::ExpectSameEpisodes(cell::RunEvaluationCell(perturbed), reference);
  }
}

TEST(PerturbationPairs, PerturbedCellsPairWithTheirBaseCellEpisodeByEpisode) {
  // Two seeds of a base cell and of its perturbed cell (labelled as a sweep labels them), and a
  // perturbed cell of another policy whose base cell is missing: no row.
  auto cell = [](const std::string& label, const std::vector<std::string>& perturbations, uint64_t seed,
                 const std::vector<bool>& successes) {
    report::CellEpisodes episodes;
    episodes.label = label;
    episodes.config.task = "clutter-pick-cube";
    episodes.config.robot = "gr1t2";
    episodes.config.seed = seed;
    episodes.config.perturbations = perturbations;
    for (const bool success : successes) {
      cell::EpisodeRecord record;
      record.success = success;
      episodes.episodes.push_back(record);
    }
    return episodes;
  };
  const std::vector<report::CellEpisodes> cells = {
      cell("expert", {}, 0, {true, true, true, true, false}),
      cell("expert.sensor.noise-high", {"sensor:noise-high"}, 0, {false, false, false, true, true}),
      cell("expert", {}, 1, {true, true, true, true}),
      cell("expert.sensor.noise-high", {"sensor:noise-high"}, 1, {false, true, false, false}),
      cell("other.sensor.noise-high", {"sensor:noise-high"}, 0, {true}),
  };
  const nlohmann::ordered_json rows = report::PerturbationPairRows(cells);
  ASSERT_EQ(rows.size(), 1u) << rows.dump();
  const nlohmann::ordered_json& row = rows[0];
  EXPECT_EQ(row["label"], "expert");
  EXPECT_EQ(row["perturbation"], "sensor:noise-high");
  EXPECT_EQ(row["pairs"], 9);
  EXPECT_EQ(row["both"], 2);            // seed 0 episode 3, seed 1 episode 1
  EXPECT_EQ(row["base_only"], 6);       // seed 0 episodes 0-2, seed 1 episodes 0, 2, 3
  EXPECT_EQ(row["perturbed_only"], 1);  // seed 0 episode 4
  EXPECT_EQ(row["neither"], 0);
  // McNemar: 2 P[X <= 1], X ~ Binomial(7, 1/2) = 2 * 8 / 128.
  EXPECT_NEAR(row["mcnemar_p"].get<double>(), 16.0 / 128.0, 1e-12);
  EXPECT_NEAR(row["difference"].get<double>(), 3.0 / 9.0 - 8.0 / 9.0, 1e-12);
}

}  // namespace
}  // namespace tavis::batch::perturb

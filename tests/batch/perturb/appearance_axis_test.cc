// The appearance perturbation axis (configs/perturbations/appearance.yaml,
// batch/perturb/surface_texture_yaml.h, batch/perturb/perturbed_appearance.h): the shipped levels
// load and record their settings; a bad surface is refused naming the file, the key and the value;
// a table or floor texture changes exactly the pixels that see the table or the floor (found from
// the depth image, not from the textures); a distractor texture changes only distractors and
// nothing without them; random colours are a function of (seed, episode), not of the slot; and the
// scripted expert's episodes under every level are the base cell's.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "batch/cell/evaluation_cell.h"
#include "batch/perturb/perturbation_catalog.h"
#include "batch/perturb/perturbed_appearance.h"
#include "batch/scene_render.h"
#include "batch/vec_env.h"
#include "configs/robot_config.h"
#include "configs/yaml_reader.h"
#include "engine/object_catalog.h"
#include "render/camera.h"
#include "scenarios/registry.h"
#include "tests/batch/rendered_expert_cell.h"

namespace tavis::batch::perturb {
namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 96;
constexpr int kHeight = 72;
constexpr uint64_t kSeed = 5;
// A pixel whose hit point lies within this of a surface sees that surface (the hit point is
// recovered from the float depth to well under a millimetre).
constexpr double kOnSurfaceM = 2e-3;

// What one env's four cameras show at its reset: colour, depth, object ids, and where each pixel's
// hit point is in the world (NaN where the ray saw the sky).
struct Frame {
  std::vector<std::vector<uint8_t>> rgb;  // [camera][pixel * 3]
  std::vector<std::vector<int32_t>> ids;  // [camera][pixel]
  std::vector<std::vector<Vec3>> points;  // [camera][pixel]
};

using ModelEdit = std::function<void(engine::WorldModel*)>;

// Renders `episodes` (one per slot) of clutter-pick-cube on GR1T2 at their reset under `choices`.
std::vector<Frame> RenderReset(const std::vector<std::string>& choices, const std::vector<int64_t>& episodes = {0},
                               const ModelEdit& edit = nullptr) {
  const scenarios::ScenarioDef& scenario = scenarios::FindScenario("clutter-pick-cube");
  const kinematics::RobotModel robot = configs::LoadRobotModel(configs::RobotConfigPath(TAVIS_CONFIG_DIR, "gr1t2"));
  engine::WorldModel model = BuildWorldModel(robot, scenario);
  if (edit) edit(&model);
  ApplyPerturbations(TAVIS_CONFIG_DIR, choices, kSeed, &model);
  const int slots = static_cast<int>(episodes.size());
  VecEnv env(std::move(model), scenario, scenarios::Split::kId, slots, kSeed);
  CameraSettings settings;
  settings.cameras = SceneCameraNames();
  settings.width = kWidth;
  settings.height = kHeight;
  settings.with_depth = true;
  settings.with_object_id = true;
  env.EnableCameras(settings);
  std::vector<EpisodeStart> starts;
  for (int slot = 0; slot < slots; ++slot) starts.push_back({slot, episodes[static_cast<std::size_t>(slot)]});
  env.Reset(starts);
  env.RenderPolicyTick();
  const render::ImageBatch& images = *env.images();
  const SceneRender& scene = *env.renderer();
  std::vector<Frame> frames(static_cast<std::size_t>(slots));
  for (int slot = 0; slot < slots; ++slot) {
    Frame& frame = frames[static_cast<std::size_t>(slot)];
    for (int c = 0; c < images.n_cameras(); ++c) {
      const std::size_t pixels = static_cast<std::size_t>(kWidth) * kHeight;
      frame.rgb.emplace_back(images.rgb(slot, c), images.rgb(slot, c) + 3 * pixels);
      frame.ids.emplace_back(images.object_id(slot, c), images.object_id(slot, c) + pixels);
      // The hit point: depth along the optical axis times the ray through the pixel's centre.
      const render::CameraIntrinsics k = render::IntrinsicsOf(scene.layout().cameras[static_cast<std::size_t>(c)]);
      const RigidTransform& X_WC = scene.camera_poses(slot)[c];
      std::vector<Vec3> points(pixels, Vec3::Constant(std::nan("")));
      for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; ++x) {
          const std::size_t p = static_cast<std::size_t>(y) * kWidth + x;
          const double depth = images.depth(slot, c)[p];
          if (depth <= 0.0) continue;
          const Vec3 ray_C(1.0, (k.cx - (x + 0.5)) / k.fx, (k.cy - (y + 0.5)) / k.fx);
          points[p] = X_WC * (depth * ray_C);
        }
      }
      frame.points.push_back(std::move(points));
    }
  }
  return frames;
}

Frame RenderOne(const std::vector<std::string>& choices, const ModelEdit& edit = nullptr) {
  return RenderReset(choices, {0}, edit)[0];
}

bool PixelChanged(const Frame& a, const Frame& b, std::size_t camera, std::size_t pixel) {
  for (int ch = 0; ch < 3; ++ch) {
    if (a.rgb[camera][3 * pixel + ch] != b.rgb[camera][3 * pixel + ch]) return true;
  }
  return false;
}

struct MaskCount {
  int inside = 0;          // pixels the mask says see the surface
  int inside_changed = 0;  // of those, changed
  int outside_changed = 0;
};

MaskCount CountChanges(const Frame& base, const Frame& perturbed, std::size_t camera,
                       const std::function<bool(std::size_t pixel)>& sees_surface) {
  MaskCount count;
  for (std::size_t p = 0; p < base.ids[camera].size(); ++p) {
    const bool changed = PixelChanged(base, perturbed, camera, p);
    if (sees_surface(p)) {
      ++count.inside;
      count.inside_changed += changed ? 1 : 0;
    } else {
      count.outside_changed += changed ? 1 : 0;
    }
  }
  return count;
}

// The table top's box in the world (engine::MakeTable, as the scene builds it).
struct Box {
  RigidTransform X_WB;
  Vec3 half_size;
  bool Holds(const Vec3& p_W, double margin) const {
    if (!p_W.allFinite()) return false;
    const Vec3 p = X_WB.inverse() * p_W;
    return (p.cwiseAbs() - half_size).maxCoeff() <= margin;
  }
};

Box TableBox() {
  const engine::StaticPart table = engine::MakeTable();
  return {table.X_WS, 0.5 * table.shape.size};
}

std::string LoadError(const std::string& text) {
  const fs::path dir =
      fs::temp_directory_path() / ("tavis_appearance_test_" + std::to_string(std::hash<std::string>()(text)));
  fs::create_directories(dir / "perturbations");
  std::ofstream(dir / "perturbations" / "appearance.yaml") << text;
  try {
    LoadPerturbationAxis(dir.string(), "appearance");
  } catch (const configs::ConfigError& error) {
    return error.what();
  }
  return "";
}

// An axis file of one level whose table has these "key: value" lines.
std::string LevelWithTable(const std::vector<std::string>& table) {
  std::string yaml = "axis: appearance\nlevels:\n  - name: a\n    description: x\n    table:\n";
  for (const std::string& line : table) yaml += "      " + line + "\n";
  return yaml;
}

TEST(AppearanceAxis, ShippedLevelsLoadAndRecordTheirSettings) {
  const std::vector<PerturbationLevel> levels = LoadPerturbationAxis(TAVIS_CONFIG_DIR, "appearance");
  ASSERT_GE(levels.size(), 4u);
  for (const PerturbationLevel& level : levels) {
    EXPECT_TRUE(level.effect.changes_surfaces()) << level.name;
    EXPECT_FALSE(level.effect.moves_cameras() || level.effect.changes_lighting() || level.effect.changes_images());
  }
  const std::vector<PerturbationLevel> chosen = ResolvePerturbations(TAVIS_CONFIG_DIR, {"appearance:table-checker"});
  ASSERT_EQ(chosen.size(), 1u);
  const nlohmann::json settings = PerturbationsJson(chosen)[0]["settings"];
  EXPECT_EQ(settings["table"]["pattern"], "checker");
  EXPECT_EQ(settings["table"]["scale_m"], 0.08);
  EXPECT_EQ(settings["table"]["colours"][1][2], 0.14);
  const engine::SurfaceTexture& table = chosen[0].effect.table_texture;
  EXPECT_EQ(table.pattern, engine::TexturePattern::kChecker);
  EXPECT_FLOAT_EQ(table.colour_a.x(), 0.75f);
  EXPECT_FALSE(chosen[0].effect.floor_texture.textured());
  const std::vector<PerturbationLevel> random =
      ResolvePerturbations(TAVIS_CONFIG_DIR, {"appearance:table-random-colour"});
  EXPECT_EQ(PerturbationsJson(random)[0]["settings"]["table"]["colours"], "random");
  EXPECT_TRUE(random[0].effect.table_texture.random_colours);
}

TEST(AppearanceAxis, BadSurfacesAreRefusedNamingFileKeyAndValue) {
  struct Case {
    std::vector<std::string> table;     // the level's table: "key: value" lines
    std::vector<std::string> expected;  // substrings of the error
  };
  const std::string two_colours = "colours: [[0, 0, 0], [1, 1, 1]]";
  const std::vector<Case> cases = {
      {{"pattern: plaid", "scale_m: 0.1", two_colours},
       {"appearance.yaml", "levels[0].table.pattern", "plaid", "checker"}},
      {{"pattern: checker", "scale_m: 0", two_colours}, {"levels[0].table.scale_m", "0"}},
      {{"pattern: checker", "scale_m: 0.1", "colours: [[0, 0, 0]]"}, {"table.colours", "2 colours"}},
      {{"pattern: checker", "scale_m: 0.1", "colours: [[0, 0, 0], [1, 1.5, 1]]"}, {"table.colours[1]", "1.5"}},
      {{"pattern: checker", "scale_m: 0.1", "colours: rainbow"}, {"table.colours", "rainbow"}},
      {{"pattern: checker", "scale_m: 0.1", "colours: random", "turbulence: 1"}, {"table.turbulence", "no turbulence"}},
      {{"pattern: solid", "scale_m: 0.1", "colours: [[0, 0, 0]]"}, {"table.scale_m", "no scale_m"}},
      {{"pattern: stripes", "scale_m: 0.1", "colours: random", "angle_deg: 200"}, {"table.angle_deg", "200"}},
      {{"pattern: stripes", "scale_m: 0.1", "colour: random"}, {"table", "colours"}},
      {{"pattern: wood", "scale_m: 0.1", "colours: random", "grain: 2"}, {"table.grain", "unknown"}},
  };
  for (const Case& c : cases) {
    const std::string error = LoadError(LevelWithTable(c.table));
    for (const std::string& part : c.expected) EXPECT_NE(error.find(part), std::string::npos) << error;
  }
  const std::string nothing = LoadError("axis: appearance\nlevels:\n  - name: a\n    description: x\n");
  EXPECT_NE(nothing.find("distractors"), std::string::npos) << "lists the axis's keys: " << nothing;
}

TEST(AppearanceAxis, TableAndFloorTexturesChangeExactlyThePixelsThatSeeThem) {
  const Frame base = RenderOne({});
  const Box table = TableBox();
  struct Case {
    const char* level;
    std::function<bool(const Vec3&)> on_surface;
  };
  const std::vector<Case> cases = {
      {"table-checker", [&](const Vec3& p) { return table.Holds(p, kOnSurfaceM); }},
      {"table-wood", [&](const Vec3& p) { return table.Holds(p, kOnSurfaceM); }},
      {"floor-stripes", [](const Vec3& p) { return p.allFinite() && std::fabs(p.z()) < kOnSurfaceM; }},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.level);
    const Frame textured = RenderOne({std::string("appearance:") + c.level});
    EXPECT_EQ(textured.ids, base.ids) << "the same objects where they were";
    int seen = 0;
    for (std::size_t camera = 0; camera < base.rgb.size(); ++camera) {
      SCOPED_TRACE(SceneCameraNames()[camera]);
      const MaskCount count =
          CountChanges(base, textured, camera, [&](std::size_t p) { return c.on_surface(base.points[camera][p]); });
      EXPECT_EQ(count.outside_changed, 0) << "the robot, the objects and the rest are byte-identical";
      if (count.inside > 100) {
        ++seen;
        EXPECT_GT(count.inside_changed, count.inside / 3);
      }
    }
    EXPECT_GE(seen, 2) << "the surface is in view of at least two cameras";
  }
}

TEST(AppearanceAxis, DistractorTexturesChangeOnlyDistractorsAndNothingWithoutThem) {
  const Frame base = RenderOne({});
  EXPECT_EQ(RenderOne({"appearance:distractors-checker"}).rgb, base.rgb) << "no distractors: no change";
  // The task's object most in view, flagged as a distractor, stands in for the distractors axis's.
  std::map<int32_t, int> pixels_of;
  for (const std::vector<int32_t>& ids : base.ids) {
    for (const int32_t id : ids) ++pixels_of[id];
  }
  int32_t flagged = -1;
  for (const auto& [id, pixels] : pixels_of) {
    if (id >= 0 && (flagged < 0 || pixels > pixels_of[flagged])) flagged = id;
  }
  ASSERT_GE(flagged, 0);
  const ModelEdit flag = [flagged](engine::WorldModel* model) { model->objects[flagged].distractor = true; };
  const Frame flagged_base = RenderOne({}, flag);
  EXPECT_EQ(flagged_base.rgb, base.rgb) << "the flag alone changes nothing";
  const Frame textured = RenderOne({"appearance:distractors-checker"}, flag);
  int inside = 0;
  for (std::size_t camera = 0; camera < base.rgb.size(); ++camera) {
    const MaskCount count =
        CountChanges(base, textured, camera, [&](std::size_t p) { return base.ids[camera][p] == flagged; });
    EXPECT_EQ(count.outside_changed, 0) << SceneCameraNames()[camera];
    EXPECT_GE(count.inside_changed, count.inside / 4) << SceneCameraNames()[camera];
    inside += count.inside;
  }
  EXPECT_GT(inside, 30) << "the flagged object is in view";
}

TEST(AppearanceAxis, RandomColoursFollowTheEpisodeNotTheSlot) {
  const Box table = TableBox();
  const std::vector<Frame> ordered = RenderReset({"appearance:table-random-colour"}, {0, 1});
  const std::vector<Frame> swapped = RenderReset({"appearance:table-random-colour"}, {1, 0});
  EXPECT_EQ(ordered[0].rgb, swapped[1].rgb) << "episode 0 looks the same in either slot";
  EXPECT_EQ(ordered[1].rgb, swapped[0].rgb);
  const std::vector<Frame> base = RenderReset({}, {0, 1});
  const std::size_t fixed = 1;  // SceneCameraNames(): head, fixed, left_wrist, right_wrist
  for (int episode = 0; episode < 2; ++episode) {
    const Frame& b = base[static_cast<std::size_t>(episode)];
    const MaskCount count = CountChanges(b, ordered[static_cast<std::size_t>(episode)], fixed,
                                         [&](std::size_t p) { return table.Holds(b.points[fixed][p], kOnSurfaceM); });
    EXPECT_EQ(count.outside_changed, 0);
    EXPECT_GT(count.inside_changed, count.inside / 2);
  }
  // Two episodes draw two colours (the base scenes differ too, so compare the textures).
  const engine::RenderPerturbation level =
      ResolvePerturbations(TAVIS_CONFIG_DIR, {"appearance:table-random-colour"})[0].effect;
  engine::RenderPerturbation seeded = level;
  seeded.noise_seed = kSeed;
  const EpisodeTextures first = TexturesOfEpisode(seeded, 0);
  EXPECT_NE(first.table.colour_a, TexturesOfEpisode(seeded, 1).table.colour_a);
  EXPECT_EQ(first.table.colour_a, TexturesOfEpisode(seeded, 0).table.colour_a);
  seeded.noise_seed = kSeed + 1;
  EXPECT_NE(first.table.colour_a, TexturesOfEpisode(seeded, 0).table.colour_a) << "another seed, other colours";
}

TEST(AppearanceAxis, EveryLevelLeavesTheExpertsEpisodesExactlyAsInTheBaseCell) {
  // One GR1T2 episode per level (the view axes' test runs Reachy2).
  const cell::EvaluationCellConfig base = testing::RenderedExpertCell("gr1t2", 1, 3);
  const cell::CellResult reference = cell::RunEvaluationCell(base);
  ASSERT_EQ(reference.episodes.size(), 1u);
  ASSERT_GT(reference.rendered_images, 0) << "the cameras are rendered, under the level, every policy tick";
  for (const PerturbationLevel& level : LoadPerturbationAxis(TAVIS_CONFIG_DIR, "appearance")) {
    SCOPED_TRACE(level.name);
    cell::EvaluationCellConfig perturbed = base;
    perturbed.perturbations = {"appearance:" + level.name};
    const cell::CellResult result = cell::RunEvaluationCell(perturbed);
    EXPECT_EQ(result.rendered_images, reference.rendered_images);
    testing::ExpectSameEpisodes(result, reference);
  }
}

}  // namespace
}  // namespace tavis::batch::perturb

// `tavis render`: the four camera views of one episode at its reset and after N control ticks
// of the scripted expert, as PNG files and a labelled contact sheet, for looking at the scene.
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "batch/builtin_policies.h"
#include "batch/scene_render.h"
#include "batch/vec_env.h"
#include "configs/robot_config.h"
#include "render/image_io.h"
#include "scenarios/registry.h"
#include "tools/commands.h"
#include "tools/option_parsing.h"

namespace tavis::tools {
namespace {

struct RenderCommandOptions {
  std::string task = "clutter-pick-cube";
  std::string robot = "gr1t2";
  std::string split = "id";
  int64_t seed = 0;
  int64_t episode = 0;
  std::string out;
  int width = 640;
  int height = 480;
  int steps = 120;
  std::string config_dir;
};

void RequirePositive(const char* option, int value) {
  if (value < 1) throw std::invalid_argument(std::string(option) + " " + std::to_string(value) + " must be at least 1");
}

// Writes one PNG per camera, DIR/<prefix>_<camera>.png, and returns the paths.
std::vector<std::string> WriteViews(const batch::SceneRender& scene, const std::filesystem::path& dir,
                                    const std::string& prefix) {
  std::vector<std::string> paths;
  const render::ImageBatch& images = scene.images();
  for (int c = 0; c < scene.num_cameras(); ++c) {
    const std::string path = (dir / (prefix + "_" + scene.settings().cameras[static_cast<std::size_t>(c)] + ".png")).string();
    render::WritePng(path, images.height(c), images.width(c), images.rgb(0, c));
    paths.push_back(path);
  }
  return paths;
}

void RunRender(const RenderCommandOptions& options) {
  // Every input is checked before anything is simulated or written.
  const scenarios::ScenarioDef& scenario = scenarios::FindScenario(options.task);
  const scenarios::Split split = scenarios::ParseSplit(options.split);
  if (options.seed < 0) throw std::invalid_argument("--seed " + std::to_string(options.seed) + " must be >= 0");
  if (options.episode < 0) throw std::invalid_argument("--episode " + std::to_string(options.episode) + " must be >= 0");
  if (options.steps < 0) throw std::invalid_argument("--steps " + std::to_string(options.steps) + " must be >= 0");
  RequirePositive("--width", options.width);
  RequirePositive("--height", options.height);
  const kinematics::RobotModel robot = configs::LoadRobotModel(configs::RobotConfigPath(options.config_dir, options.robot));

  batch::VecEnv env(batch::BuildWorldModel(robot, scenario), scenario, split, 1, static_cast<uint64_t>(options.seed));
  batch::CameraSettings settings;
  settings.cameras = batch::SceneCameraNames();
  settings.width = options.width;
  settings.height = options.height;
  batch::SceneRender scene(env.model(), 1, settings);
  // As the policy receives them: a task's black cameras (blocked-clutter-pick-cube's head).
  for (const std::string& name : scenario.black_cameras) scene.SetCameraEnabled(0, scene.CameraIndex(name), false);
  // Tasks still without a scripted expert are shown with the robot holding its reset pose.
  const bool has_expert = scenario.make_expert != nullptr;
  std::unique_ptr<batch::Policy> expert = batch::MakeBuiltinPolicy(has_expert ? "expert" : "hold", scenario, env.model(), 1);

  const std::filesystem::path dir(options.out);
  std::filesystem::create_directories(dir);
  const uint8_t render_env = 1;
  env.ResetEnv(0, options.episode);
  expert->Reset(env.model(), env.state(), 0);
  scene.Render(env.state(), &render_env);
  std::vector<std::string> written = WriteViews(scene, dir, "reset");

  // Ticks are counted from the reset (ood-init-pose's warm-up belongs to the reset).
  std::vector<kinematics::Action> actions(1);
  const engine::BatchState& state = env.state();
  int ticks = 0;
  for (; ticks < options.steps && state.end[0] == engine::EpisodeEnd::kRunning; ++ticks) {
    expert->Act(env.model(), batch::Observation{state}, 0, actions[0]);
    env.Step(actions);
  }
  scene.Render(state, &render_env);
  const std::string tick_label = "tick " + std::to_string(ticks);
  for (const std::string& path : WriteViews(scene, dir, "tick" + std::to_string(ticks))) written.push_back(path);

  std::vector<render::LabelledImage> views;
  const render::ImageBatch& images = scene.images();
  for (int c = 0; c < scene.num_cameras(); ++c) {
    views.push_back({settings.cameras[static_cast<std::size_t>(c)] + ", " + tick_label, images.height(c), images.width(c),
                     images.rgb(0, c)});
  }
  const std::string sheet = (dir / "contact_sheet.png").string();
  render::WritePng(sheet, render::MakeContactSheet(views));
  written.push_back(sheet);

  std::cout << options.task << " " << options.robot << " " << scenarios::ToString(split) << " seed " << options.seed
            << " episode " << options.episode << ": " << tick_label;
  if (state.end[0] != engine::EpisodeEnd::kRunning) {
    std::cout << " (episode ended: " << engine::ToString(state.end[0]) << ")";
  }
  if (!has_expert) std::cout << " (no scripted expert for this task: the robot held its reset pose)";
  std::cout << "\n";
  for (const std::string& path : written) std::cout << "  " << path << "\n";
}

}  // namespace

void RegisterRenderCommand(CLI::App& app) {
  auto options = std::make_shared<RenderCommandOptions>();
  options->config_dir = TAVIS_DEFAULT_CONFIG_DIR;
  CLI::App* render = app.add_subcommand(
      "render",
      "Render the four cameras (head, fixed, left_wrist, right_wrist) of one episode at its reset and\n"
      "after --steps control ticks (60 Hz) of the scripted expert, or when the episode ends if earlier.\n"
      "Writes DIR/reset_<camera>.png, DIR/tick<T>_<camera>.png and DIR/contact_sheet.png (the four\n"
      "views at tick T, labelled). A task without a scripted expert is shown with the robot holding\n"
      "its reset pose. A camera the task blacks out (blocked-clutter-pick-cube's head) is\n"
      "written black, as policies receive it.");
  render->add_option("--task", options->task, "Task (" + KnownTasks() + ")")->capture_default_str();
  render->add_option("--robot", options->robot, "Robot: gr1t2 or reachy2 (configs/robots/<name>.yaml)")
      ->capture_default_str();
  render->add_option("--split", options->split, "Split: id, ood-spatial or ood-init-pose")->capture_default_str();
  render->add_option("--seed", options->seed, "Seed: the episode draws its randomness from (seed, episode)")
      ->capture_default_str();
  render->add_option("--episode", options->episode, "Episode index within the seed")->capture_default_str();
  render->add_option("--out", options->out, "Output directory (created if missing)")->required();
  render->add_option("--width", options->width, "Image width in pixels")->capture_default_str();
  render->add_option("--height", options->height, "Image height in pixels")->capture_default_str();
  render->add_option("--steps", options->steps, "Control ticks (60 Hz) of the expert before the second render")
      ->capture_default_str();
  render->add_option("--config-dir", options->config_dir, "Directory holding robots/*.yaml")->capture_default_str();
  render->callback([options] { RunRender(*options); });
}

}  // namespace tavis::tools

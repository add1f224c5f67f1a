// `tavis render`: the four camera views of one episode at its reset and after N control ticks
// of the scripted expert, as PNG files and a labelled contact sheet, for looking at the scene.
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "batch/builtin_policies.h"
#include "batch/episode_driver.h"
#include "batch/policy_kinds.h"
#include "batch/scene/scene_plan.h"
#include "batch/scene_render.h"
#include "batch/vec_env.h"
#include "render/image_io.h"
#include "scenarios/registry.h"
#include "tools/commands.h"
#include "tools/option_parsing.h"
#include "tools/scene_options.h"

namespace tavis::tools {
namespace {

struct RenderCommandOptions {
  batch::scene::SceneSpec scene;  // --task, --robot, --split, --seed, --perturb, --config-dir
  int64_t episode = 0;
  std::string out;
  int width = 640;
  int height = 480;
  int steps = 120;
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
    const std::string path =
        (dir / (prefix + "_" + scene.settings().cameras[static_cast<std::size_t>(c)] + ".png")).string();
    render::WritePng(path, images.height(c), images.width(c), images.rgb(0, c));
    paths.push_back(path);
  }
  return paths;
}

// Renders the four cameras of the one episode at its start and where it stops (after `steps`
// control ticks counted from the reset, ood-init-pose's warm-up belonging to the reset, or at its
// end if earlier), writing the views as it goes.
class ViewWriter : public batch::EpisodeSink {
 public:
  ViewWriter(const batch::VecEnv& vec_env, const batch::CameraSettings& settings, int steps, std::filesystem::path dir)
      : scene_(vec_env.model(), 1, settings), steps_(steps), dir_(std::move(dir)) {
    // As the policy receives them: a task's black cameras (blocked-clutter-pick-cube's head).
    for (const std::string& name : vec_env.scenario().black_cameras) {
      scene_.SetCameraEnabled(0, scene_.CameraIndex(name), false);
    }
  }

  void EpisodeStarted(const batch::VecEnv& vec_env, int) override {
    Render(vec_env);
    for (const std::string& path : WriteViews(scene_, dir_, "reset")) written_.push_back(path);
  }
  void Stepped(const batch::VecEnv&) override { ++ticks_; }
  bool EpisodeComplete(const batch::VecEnv&, int) const override { return ticks_ >= steps_; }
  void EpisodeEnded(const batch::VecEnv& vec_env, int) override {
    end_ = vec_env.state().end[0];
    Render(vec_env);
    for (const std::string& path : WriteViews(scene_, dir_, "tick" + std::to_string(ticks_))) written_.push_back(path);
    std::vector<render::LabelledImage> views;
    const render::ImageBatch& images = scene_.images();
    for (int c = 0; c < scene_.num_cameras(); ++c) {
      views.push_back({scene_.settings().cameras[static_cast<std::size_t>(c)] + ", " + tick_label(), images.height(c),
                       images.width(c), images.rgb(0, c)});
    }
    const std::string sheet = (dir_ / "contact_sheet.png").string();
    render::WritePng(sheet, render::MakeContactSheet(views));
    written_.push_back(sheet);
  }

  std::string tick_label() const { return "tick " + std::to_string(ticks_); }
  engine::EpisodeEnd end() const { return end_; }
  const std::vector<std::string>& written() const { return written_; }

 private:
  void Render(const batch::VecEnv& vec_env) {
    const uint8_t render_env = 1;
    scene_.Render(vec_env.state(), &render_env);
  }

  batch::SceneRender scene_;
  int steps_ = 0;
  std::filesystem::path dir_;
  int ticks_ = 0;
  engine::EpisodeEnd end_ = engine::EpisodeEnd::kRunning;
  std::vector<std::string> written_;
};

void RunRender(const RenderCommandOptions& options) {
  // Every input is checked before anything is simulated or written.
  const batch::scene::SceneSpec& spec = options.scene;
  if (options.episode < 0)
    throw std::invalid_argument("--episode " + std::to_string(options.episode) + " must be >= 0");
  if (options.steps < 0) throw std::invalid_argument("--steps " + std::to_string(options.steps) + " must be >= 0");
  RequirePositive("--width", options.width);
  RequirePositive("--height", options.height);
  batch::scene::ScenePlan plan = batch::scene::PlanScene(spec);
  const scenarios::ScenarioDef& scenario = *plan.scenario;
  batch::VecEnv vec_env(std::move(plan.model), scenario, spec.split, 1, spec.seed);
  batch::CameraSettings settings;
  settings.cameras = batch::SceneCameraNames();
  settings.width = options.width;
  settings.height = options.height;
  // Tasks still without a scripted expert are shown with the robot holding its reset pose.
  const bool has_expert = scenario.make_expert != nullptr;
  std::unique_ptr<batch::Policy> policy =
      batch::MakeBuiltinPolicy(batch::PolicyName(has_expert ? batch::PolicyKind::kExpert : batch::PolicyKind::kHold),
                               scenario, vec_env.model(), 1);

  const std::filesystem::path dir(options.out);
  std::filesystem::create_directories(dir);
  ViewWriter views(vec_env, settings, options.steps, dir);
  batch::EpisodeDriver driver(vec_env, *policy, 1, options.episode);
  driver.AddSink(views);
  driver.Run();

  std::cout << spec.task << " " << spec.robot << " " << scenarios::ToString(spec.split) << " seed " << spec.seed
            << " episode " << options.episode << ": " << views.tick_label();
  if (views.end() != engine::EpisodeEnd::kStopped) {
    std::cout << " (episode ended: " << engine::ToString(views.end()) << ")";
  }
  if (!has_expert) std::cout << " (no scripted expert for this task: the robot held its reset pose)";
  std::cout << "\n  prompt: " << vec_env.prompt(0) << "\n";
  // A runtime level's move (docs/perturbations.md), which the views may come before or after.
  if (vec_env.model().episode_perturbation.moves_target()) {
    const int moved = vec_env.state().task[0].target_move_tick;
    std::cout << "  target " << (moved >= 0 ? "moved at tick " + std::to_string(moved) : "not moved") << "\n";
  }
  for (const std::string& path : views.written()) std::cout << "  " << path << "\n";
}

}  // namespace

void RegisterRenderCommand(CLI::App& app) {
  auto options = std::make_shared<RenderCommandOptions>();
  CLI::App* render = app.add_subcommand(
      "render",
      "Render the four cameras (head, fixed, left_wrist, right_wrist) of one episode at its reset and\n"
      "after --steps control ticks (60 Hz) of the scripted expert, or when the episode ends if earlier.\n"
      "Writes DIR/reset_<camera>.png, DIR/tick<T>_<camera>.png and DIR/contact_sheet.png (the four\n"
      "views at tick T, labelled). A task without a scripted expert is shown with the robot holding\n"
      "its reset pose. A camera the task blacks out (blocked-clutter-pick-cube's head) is\n"
      "written black, as policies receive it.");
  batch::scene::SceneSpec& scene = options->scene;
  AddSceneOptions(*render, {&scene.task, &scene.robot, &scene.split, &scene.seed, &scene.perturbations, nullptr,
                            &scene.config_dir});
  render->add_option("--episode", options->episode, "Episode index within the seed")
      ->check(IntegerIn(0, 1000000000))
      ->capture_default_str();
  render->add_option("--out", options->out, "Output directory (created if missing)")->required();
  render->add_option("--width", options->width, "Image width in pixels")
      ->check(IntegerIn(1, 8192))
      ->capture_default_str();
  render->add_option("--height", options->height, "Image height in pixels")
      ->check(IntegerIn(1, 8192))
      ->capture_default_str();
  render->add_option("--steps", options->steps, "Control ticks (60 Hz) of the expert before the second render")
      ->check(IntegerIn(0, 1000000))
      ->capture_default_str();
  render->callback([options] { RunRender(*options); });
}

}  // namespace tavis::tools

// `tavis audit`: in how many episodes each camera sees a task's target and cue at reset and at
// the scripted expert's fixation, as a table on stdout and optionally DIR/audit.json.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <nlohmann/json.hpp>

#include "batch/audit/visibility_audit.h"
#include "configs/robot_config.h"
#include "scenarios/registry.h"
#include "tools/commands.h"
#include "tools/option_parsing.h"
#include "tools/scene_options.h"

namespace tavis::tools {
namespace {

constexpr const char* kVisibleDefinition = ">=1% of the object's pixels";

struct AuditOptions {
  batch::audit::AuditConfig audit;
  std::string image_size = "224x224";
  std::string out;
  bool all = false;
  int threads = 0;
  bool quiet = false;
};

std::string Share(int count, int total) {
  char text[32];
  std::snprintf(text, sizeof(text), "%3d/%-3d %5.1f%%", count, total, total > 0 ? 100.0 * count / total : 0.0);
  return text;
}

// One row per (task, robot,) object and camera; the fixation column counts among the episodes
// whose expert fixated the object, and the last column the episodes it never did.
void PrintTable(const std::vector<batch::audit::AuditResult>& results, const AuditOptions& options) {
  const batch::audit::AuditConfig& config = options.audit;
  const bool combined = results.size() > 1;
  const std::string what = combined ? "every task" : config.scene.task + " " + config.scene.robot;
  std::printf("%s %s, %d episodes, %dx%d, visible = %s\n", what.c_str(), scenarios::ToString(config.scene.split),
              config.episodes, config.image_width, config.image_height, kVisibleDefinition);
  if (combined) std::printf("%-26s %-8s ", "task", "robot");
  std::printf("%-13s %-12s %-15s %-15s %s\n", "object", "camera", "at reset", "at fixation", "never fixated");
  for (const batch::audit::AuditResult& result : results) {
    const int episodes = static_cast<int>(result.episodes.size());
    for (std::size_t o = 0; o < result.objects.size(); ++o) {
      const int fixated = result.Fixated(static_cast<int>(o));
      for (std::size_t c = 0; c < result.cameras.size(); ++c) {
        if (combined) std::printf("%-26s %-8s ", result.config.scene.task.c_str(), result.config.scene.robot.c_str());
        std::printf("%-13s %-12s %-15s %-15s %d\n", result.objects[o].c_str(), result.cameras[c].c_str(),
                    Share(result.VisibleAtReset(static_cast<int>(o), static_cast<int>(c)), episodes).c_str(),
                    Share(result.VisibleAtFixation(static_cast<int>(o), static_cast<int>(c)), fixated).c_str(),
                    episodes - fixated);
      }
    }
  }
}

nlohmann::json CameraJson(const std::vector<std::string>& cameras, const std::vector<double>& fractions) {
  nlohmann::json json;
  for (std::size_t c = 0; c < cameras.size(); ++c) json[cameras[c]] = fractions[c];
  return json;
}

nlohmann::json CellJson(const batch::audit::AuditResult& result) {
  nlohmann::json summary = nlohmann::json::array();
  for (std::size_t o = 0; o < result.objects.size(); ++o) {
    for (std::size_t c = 0; c < result.cameras.size(); ++c) {
      const int object = static_cast<int>(o);
      const int camera = static_cast<int>(c);
      summary.push_back({{"object", result.objects[o]},
                         {"camera", result.cameras[c]},
                         {"visible_at_reset", result.VisibleAtReset(object, camera)},
                         {"fixated", result.Fixated(object)},
                         {"visible_at_fixation", result.VisibleAtFixation(object, camera)}});
    }
  }
  nlohmann::json episodes = nlohmann::json::array();
  for (const batch::audit::EpisodeAudit& episode : result.episodes) {
    nlohmann::json objects;
    for (std::size_t o = 0; o < result.objects.size(); ++o) {
      const batch::audit::ObjectAudit& audit = episode.objects[o];
      objects[result.objects[o]] = {
          {"at_reset", CameraJson(result.cameras, audit.at_reset)},
          {"at_fixation", audit.at_fixation ? CameraJson(result.cameras, *audit.at_fixation) : nlohmann::json()},
          {"fixation_tick", audit.at_fixation ? nlohmann::json(audit.fixation_tick) : nlohmann::json()}};
    }
    episodes.push_back({{"episode", episode.episode}, {"objects", objects}});
  }
  return {{"task", result.config.scene.task},
          {"robot", result.config.scene.robot},
          {"wall_s", result.wall_s},
          {"summary", summary},
          {"episodes", episodes}};
}

// DIR/audit.json; nothing else in DIR is touched.
void WriteAuditJson(const std::vector<batch::audit::AuditResult>& results, const AuditOptions& options) {
  const batch::audit::AuditConfig& config = options.audit;
  nlohmann::json cells = nlohmann::json::array();
  for (const batch::audit::AuditResult& result : results) cells.push_back(CellJson(result));
  nlohmann::json json = {{"split", scenarios::ToString(config.scene.split)},
                         {"seed", config.scene.seed},
                         {"episodes", config.episodes},
                         {"image_width", config.image_width},
                         {"image_height", config.image_height},
                         {"visible", kVisibleDefinition},
                         {"visible_fraction", batch::audit::kVisibleFraction},
                         {"cells", cells}};
  // Only a perturbed audit names its levels, so an unperturbed audit.json is as it was.
  if (!config.scene.perturbations.empty()) json["perturbations"] = config.scene.perturbations;
  std::filesystem::create_directories(options.out);
  const std::filesystem::path path = std::filesystem::path(options.out) / "audit.json";
  std::ofstream out(path);
  out << json.dump(2) << "\n";
  if (!out.flush()) throw std::runtime_error("cannot write " + path.string());
}

void RunAudit(AuditOptions options, bool task_or_robot_given) {
  batch::audit::AuditConfig& config = options.audit;
  // Every input is checked before anything is simulated.
  std::tie(config.image_width, config.image_height) = ParseImageSize(options.image_size);
  if (options.all && task_or_robot_given)
    throw std::invalid_argument("--all audits every task on both robots; drop --task and --robot");
  scenarios::FindScenario(config.scene.task);
  const int threads = options.threads > 0 ? options.threads : tbb::info::default_concurrency();
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));

  std::vector<batch::audit::AuditConfig> cells = {config};
  if (options.all) {
    cells.clear();
    for (const auto& scenario : scenarios::AllScenarios()) {
      for (const std::string& robot : configs::KnownRobots(config.scene.config_dir)) {
        cells.push_back(config);
        cells.back().scene.task = scenario.name;
        cells.back().scene.robot = robot;
      }
    }
  }
  std::vector<batch::audit::AuditResult> results;
  for (const batch::audit::AuditConfig& cell : cells) {
    results.push_back(batch::audit::RunVisibilityAudit(cell));
    if (!options.quiet) {
      std::fprintf(stderr, "audit: %s %s %s: %d episodes in %.1f s\n", cell.scene.task.c_str(),
                   cell.scene.robot.c_str(), scenarios::ToString(cell.scene.split), cell.episodes,
                   results.back().wall_s);
    }
  }
  PrintTable(results, options);
  if (!options.out.empty()) WriteAuditJson(results, options);
}

}  // namespace

void RegisterAuditCommand(CLI::App& app) {
  auto options = std::make_shared<AuditOptions>();
  CLI::App* audit = app.add_subcommand(
      "audit",
      "Visibility audit: per camera (head, fixed, left_wrist, right_wrist), in how many episodes the\n"
      "task's target (and its cue objects: conditional-pick's card, wait-then-act's light) is\n"
      "visible at reset and at the scripted expert's fixation (the first control tick its gaze is\n"
      "settled on the object; for peeking-box, once both wrists have peeked). Visible: at least 1%\n"
      "of the object's pixels show in the camera's object-id image, where the object's pixels are\n"
      "those it covers in that camera rendered with nothing else in the scene. A camera the task\n"
      "blacks out (blocked-clutter-pick-cube's head) sees nothing. The fixation column counts among\n"
      "the episodes that reached the fixation. Prints a table; --out DIR also writes DIR/audit.json\n"
      "with the counts and every episode's visible fractions.");
  batch::scene::SceneSpec& scene = options->audit.scene;
  AddSceneOptions(
      *audit, {&scene.task, &scene.robot, &scene.split, &scene.seed, &scene.perturbations, nullptr, &scene.config_dir});
  audit->add_flag("--all", options->all, "Audit every task on every robot of --config-dir at --split, in one table");
  audit->add_option("--episodes", options->audit.episodes, "Episodes per task and robot")
      ->check(IntegerIn(1, 100000000))
      ->capture_default_str();
  audit->add_option("--image-size", options->image_size, "Resolution of the four cameras, WIDTHxHEIGHT")
      ->capture_default_str();
  audit->add_option("--threads", options->threads, "Worker threads (0 = all cores; results do not depend on it)")
      ->check(IntegerIn(0, 1024))
      ->capture_default_str();
  audit->add_option("--out", options->out, "Directory for audit.json (created if missing; no other file is written)");
  audit->add_flag("--quiet", options->quiet, "No progress lines on stderr");
  audit->callback([options, audit] { RunAudit(*options, audit->count("--task") + audit->count("--robot") > 0); });
}

}  // namespace tavis::tools

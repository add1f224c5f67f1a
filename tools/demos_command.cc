// `tavis demos`: scripted-expert demonstrations written as a LeRobot dataset.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <nlohmann/json.hpp>

#include "batch/dataset/demo_generation.h"
#include "batch/dataset/video/video_log.h"
#include "batch/output/atomic_file.h"
#include "batch/output/output_folder.h"
#include "batch/scene_render.h"
#include "scenarios/registry.h"
#include "tools/commands.h"
#include "tools/error_text.h"
#include "tools/interrupt_notice.h"
#include "tools/option_parsing.h"
#include "tools/progress_reporter.h"
#include "tools/scene_options.h"

namespace tavis::tools {
namespace {

struct DemosOptions {
  batch::dataset::DemoConfig config;
  std::string task = "clutter-pick-cube";
  bool task_given = false;
  std::string suite;
  std::string image_size = "640x480";
  std::string cameras = "head,fixed,left_wrist,right_wrist";
  std::string codec = "h264";
  std::string format = "v3.0";
  int threads = 0;
  bool overwrite = false;
  bool quiet = false;
};

constexpr const char* kIncompleteMarker = "INCOMPLETE";

// The dataset's folder must hold no results yet, unless the user asked to replace the dataset
// tavis wrote there (built beside it and swapped in once complete) or to resume the interrupted
// recording it holds. Returns the lock on --out, held until the program ends.
batch::output::OutputLock PrepareOutput(const std::string& out, bool overwrite, bool resume,
                                        std::unique_ptr<batch::output::OutputReplacement>* replacement) {
  namespace fs = std::filesystem;
  batch::output::RequireUsableOutputPath(out);
  if (overwrite && resume) throw std::invalid_argument("give --overwrite or --resume, not both");
  if (resume) {
    if (!fs::exists(fs::path(out) / kIncompleteMarker)) {
      throw std::invalid_argument("--resume: " + out + " holds no interrupted recording (no " + kIncompleteMarker +
                                  " marker)");
    }
    return batch::output::OutputLock(out, "demos");
  }
  if (!batch::output::HoldsNoResults(out)) {
    if (!overwrite) {
      throw std::invalid_argument("--out " + out +
                                  " is not empty; give --overwrite to replace the dataset tavis wrote there, or "
                                  "--resume to finish an interrupted recording");
    }
    batch::output::RequireEmptyOrOwn(
        out, batch::output::OutputKind::kDataset,
        "--overwrite replaces only a dataset tavis wrote: move those files away or give another --out");
  }
  batch::output::OutputLock lock = batch::output::CreateAndLockOutput(out, "demos");
  if (!batch::output::HoldsNoResults(out))
    *replacement = std::make_unique<batch::output::OutputReplacement>(out, "demos");
  batch::output::WriteOutputMarker(*replacement ? (*replacement)->staging() : fs::path(out),
                                   batch::output::OutputKind::kDataset);
  return lock;
}

// What an interrupted recording into `out` kept, and the command that finishes it (Ctrl-C's line):
// the episodes saved in its spool (batch/dataset/episode_spool.h), which --resume keeps.
std::string InterruptedDatasetLine(const std::filesystem::path& out) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (fs::exists(batch::output::StagingFolderOf(out), error)) {
    return "interrupted: the new dataset was not finished and " + out.string() +
           " is as it was; run the command again to replace it";
  }
  int64_t kept = 0;
  fs::directory_iterator entry(out / ".tavis_spool", error), end;
  for (; !error && entry != end; entry.increment(error)) kept += fs::exists(entry->path() / "episode.json") ? 1 : 0;
  return KeptLine(kept, out, "the dataset", CommandLineWith({"--overwrite", "--resume"}, {}, "--resume"));
}

nlohmann::ordered_json ReportJson(const batch::dataset::DemoReport& report, const DemosOptions& options) {
  nlohmann::ordered_json tasks = nlohmann::ordered_json::array();
  for (const batch::dataset::DemoTaskReport& task : report.tasks) {
    tasks.push_back({{"task", task.task},
                     {"written", task.written},
                     {"attempts", task.attempts},
                     {"failures", task.failures},
                     {"surplus_successes", task.surplus}});
  }
  const batch::dataset::DemoConfig& config = options.config;
  return {{"robot", config.robot},
          {"split", scenarios::ToString(config.split)},
          {"expert_mode", scenarios::expert::ToString(config.expert_mode)},
          {"perturbations", config.perturbations},
          {"seed", config.seed},
          {"episodes_per_task", config.episodes},
          {"fps", config.fps},
          {"expert_hz", config.expert_hz},
          {"image_size", options.image_size},
          {"cameras", config.cameras},
          {"codec", options.codec},
          {"crf", config.video.crf},
          {"format", options.format},
          {"envs", config.envs},
          {"tasks", tasks},
          {"episodes", report.episodes},
          {"resumed_episodes", report.resumed},
          {"frames", report.frames},
          {"bytes", report.bytes},
          {"bytes_per_episode", report.episodes > 0 ? report.bytes / report.episodes : 0},
          {"wall_s", report.wall_s},
          {"seconds",
           {{"simulate", report.simulate_s},
            {"render", report.render_s},
            {"encode", report.encode_s},
            {"capture", report.capture_s},
            {"write", report.write_s}}}};
}

void RunDemos(DemosOptions options) {
  batch::dataset::DemoConfig& config = options.config;
  if (options.task_given && !options.suite.empty())
    throw std::invalid_argument("give either --task or --suite, not both");
  if (!options.suite.empty()) {
    for (const scenarios::ScenarioDef* scenario : scenarios::SuiteScenarios(scenarios::ParseSuite(options.suite))) {
      config.tasks.push_back(scenario->name);
    }
  } else {
    config.tasks = {options.task};
    scenarios::FindScenario(config.tasks.front());
  }
  std::tie(config.video.width, config.video.height) = ParseImageSize(options.image_size);
  config.cameras = options.cameras.empty() ? std::vector<std::string>{} : batch::ParseCameraList(options.cameras);
  config.video.codec = batch::dataset::video::ParseVideoCodec(options.codec);
  config.version = batch::dataset::ParseDatasetVersion(options.format);
  if (config.out.empty()) {
    config.out =
        "datasets/tavis-" + (options.suite.empty() ? config.tasks.front() : options.suite) + "-" + config.robot;
  }
  const int threads = options.threads > 0 ? options.threads : tbb::info::default_concurrency();
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
  // Every value is checked before --out is touched: a bad one must not remove what --overwrite would.
  batch::dataset::ValidateDemoConfig(config);
  std::unique_ptr<batch::output::OutputReplacement> replacement;
  const batch::output::OutputLock lock = PrepareOutput(config.out, options.overwrite, config.resume, &replacement);
  const std::string out = config.out;
  if (replacement) config.out = replacement->staging().string();
  SetInterruptNotice([out] { return InterruptedDatasetLine(out); });
  batch::dataset::video::ShowOnlyVideoErrors();
  // Until the dataset is finished the folder says so: its files are still FILE.partial and it has
  // no meta/info.json, so no loader takes it for a dataset.
  const std::filesystem::path marker = std::filesystem::path(config.out) / kIncompleteMarker;
  batch::output::WriteFileAtomically(marker,
                                     "tavis demos is writing this dataset, or was interrupted: it is complete once "
                                     "meta/info.json exists and this file is gone.\n");

  ProgressReporter reporter(stderr, ProgressReporter::StyleFor(stderr));
  const batch::dataset::DemoProgress progress = [&options, &reporter](const std::string& task, int64_t written,
                                                                      int64_t wanted) {
    if (!options.quiet) reporter.Update(task + " (written)", written, wanted);
  };
  const batch::dataset::DemoReport report = batch::dataset::GenerateDemos(config, progress);
  batch::output::WriteFileAtomically(std::filesystem::path(config.out) / "tavis_demos.json",
                                     ReportJson(report, options).dump(2) + "\n");
  std::filesystem::remove(marker);
  if (replacement) {
    replacement->SwapIn();
    config.out = out;
  }
  for (const batch::dataset::DemoTaskReport& task : report.tasks) {
    int64_t failed = 0;
    for (const auto& [end, count] : task.failures) failed += count;
    std::printf("%s %s %s: %lld episodes written, %lld failed of %lld attempts\n", task.task.c_str(),
                config.robot.c_str(), scenarios::ToString(config.split), static_cast<long long>(task.written),
                static_cast<long long>(failed), static_cast<long long>(task.attempts));
  }
  std::printf(
      "%s dataset: %lld episodes, %lld frames at %d fps, %.1f MB (%.2f MB per episode), %.1f s "
      "(simulate %.1f, render %.1f, encode %.1f, write %.1f) -> %s\n",
      options.format.c_str(), static_cast<long long>(report.episodes), static_cast<long long>(report.frames),
      config.fps, static_cast<double>(report.bytes) / 1e6,
      static_cast<double>(report.bytes) / 1e6 / static_cast<double>(report.episodes), report.wall_s, report.simulate_s,
      report.render_s, report.encode_s, report.write_s + report.capture_s, config.out.c_str());
}

}  // namespace

void RegisterDemosCommand(CLI::App& app) {
  auto options = std::make_shared<DemosOptions>();
  CLI::App* demos =
      app.add_subcommand("demos",
                         "Record scripted-expert demonstrations as a LeRobot dataset (v3.0, or v2.1 for openpi).\n"
                         "Successful episodes only, in episode order; failures are counted in DIR/tavis_demos.json.\n"
                         "Load it with LeRobot: LeRobotDataset(\"tavis/NAME\", root=DIR).");
  batch::dataset::DemoConfig& config = options->config;
  AddSceneOptions(*demos, {&options->task, &config.robot, &config.split, &config.seed, &config.perturbations,
                           &config.expert_mode, &config.config_dir});
  demos->add_option("--suite", options->suite, "Every task of a suite in one dataset: " + scenarios::KnownSuites());
  demos->add_option("--episodes", options->config.episodes, "Episodes written per task")
      ->check(IntegerIn(1, 10000000))
      ->capture_default_str();
  demos
      ->add_option("--max-attempts", options->config.max_attempts,
                   "Episodes tried per task before giving up (0: 2 x --episodes + 20)")
      ->check(IntegerIn(0, 100000000))
      ->capture_default_str();
  demos->add_option("--fps", options->config.fps, "Frame rate: 60 (the reference's datasets) or 20 (the policy rate)")
      ->check(IntegerNamingChoices({60, 20}))  // the rates GenerateDemos takes
      ->capture_default_str();
  demos
      ->add_option("--expert-hz", options->config.expert_hz,
                   "How often the expert's action may change: 60 (every control tick) or 20 (held for three ticks,\n"
                   "as a 20 Hz learned policy acts; its action rows served back at 20 Hz replay the episode exactly)")
      ->capture_default_str();
  demos->add_option("--image-size", options->image_size, "Camera image size WIDTHxHEIGHT (even)")
      ->capture_default_str();
  demos->add_option("--cameras", options->cameras, "Comma-separated cameras (head, fixed, left_wrist, right_wrist)")
      ->capture_default_str();
  demos
      ->add_option("--codec", options->codec,
                   "Video codec: h264 (decodes everywhere) or av1 (LeRobot's default, libsvtav1)")
      ->capture_default_str();
  demos
      ->add_option("--crf", options->config.video.crf,
                   "Video quality: the encoder's constant rate factor, lower is closer to the rendered images\n"
                   "(-1: the codec's default, h264 23, av1 30; up to 51 for h264, 63 for av1)")
      ->check(IntegerIn(-1, 63))
      ->capture_default_str();
  demos->add_option("--format", options->format, "Dataset format: v3.0 or v2.1 (one file per episode, for openpi)")
      ->capture_default_str();
  demos->add_option("--envs", options->config.envs, "Parallel env slots (the dataset does not depend on it)")
      ->check(IntegerIn(1, 4096))
      ->capture_default_str();
  demos->add_option("--threads", options->threads, "Worker threads (0 = all cores; the dataset does not depend on it)")
      ->check(IntegerIn(0, 1024))
      ->capture_default_str();
  demos->add_option("--out", options->config.out,
                    "Dataset folder (default datasets/tavis-<task|suite>-<robot>); must be empty");
  demos->add_flag("--overwrite", options->overwrite,
                  "Replace the dataset in --out (only a folder tavis wrote as a dataset; the new one is built\n"
                  "beside it and replaces it once complete)");
  demos->add_flag("--resume", options->config.resume,
                  "Finish an interrupted recording in --out (same settings): the episodes it had kept are\n"
                  "reused, the rest is recorded again");
  demos->add_flag("--quiet", options->quiet,
                  "No progress (episodes written, rate, ETA; a status line on a terminal, else a line per tenth)");
  demos->callback([options, demos] {
    if (demos->count("--out") > 0 && options->config.out.empty()) {
      throw std::invalid_argument("--out must name a folder, got an empty string");
    }
    options->task_given = demos->count("--task") > 0;
    RunNamingFlags([&options] { RunDemos(*options); });
  });
}

}  // namespace tavis::tools

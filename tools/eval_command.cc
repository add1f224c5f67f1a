// `tavis eval`: one evaluation cell, written to DIR/episodes.jsonl and DIR/summary.json, or one
// cell per task of a suite.
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <tbb/global_control.h>
#include <tbb/info.h>

#include "batch/cell/cell_folder.h"
#include "batch/cell/cell_folder_name.h"
#include "batch/cell/cell_profile.h"
#include "batch/cell/cell_report.h"
#include "batch/cell/declared_contract.h"
#include "batch/cell/evaluation_cell.h"
#include "batch/dataset/video/video_log.h"
#include "batch/output/atomic_file.h"
#include "batch/output/output_folder.h"
#include "batch/policy_kinds.h"
#include "batch/remote/observation_keys.h"
#include "batch/remote/remote_policy.h"
#include "batch/rollout/cell_recording.h"
#include "batch/rollout/cell_videos.h"
#include "batch/scene_render.h"
#include "scenarios/registry.h"
#include "tools/cell_options.h"
#include "tools/commands.h"
#include "tools/error_text.h"
#include "tools/interrupt_notice.h"
#include "tools/option_parsing.h"
#include "tools/progress_reporter.h"
#include "tools/scene_options.h"

namespace tavis::tools {
namespace {

struct EvalOptions {
  batch::cell::EvaluationCellConfig cell;  // its options are the table's (cell_options.h)
  std::string out;
  std::string render_cameras;
  std::string image_size;
  std::string suite;
  bool task_given = false;
  bool image_size_given = false;
  bool envs_given = false;
  int threads = 0;
  bool quiet = false;
  bool overwrite = false;
  bool resume = false;
  bool one_episode = false;                     // --episode I
  batch::rollout::EpisodeVideoSettings videos;  // --videos N and how they look
  std::string video_cameras;
  std::string video_size = "320x240";
  std::string video_format = "mp4";
  batch::rollout::RolloutDatasetSettings record;  // --record DIR: the cell's rollouts as a LeRobot dataset
  std::string record_cameras;
  std::string record_size = "320x240";
};

// --record DIR: a new or empty folder, locked for this run and marked as a dataset tavis writes.
batch::output::OutputLock PrepareRolloutDataset(const std::string& root, const std::string& cell_out) {
  batch::output::RequireUsableOutputPath(root);
  // Neither may hold the other: the dataset would be a foreign file in the cell (blocking its
  // --resume and --overwrite), or the cell one in the dataset.
  if (batch::output::IsSameOrInside(root, cell_out)) {
    throw std::invalid_argument("--record " + root + " is inside the cell's --out " + cell_out +
                                ": give the dataset a folder of its own, outside the cell");
  }
  if (batch::output::IsSameOrInside(cell_out, root)) {
    throw std::invalid_argument("--out " + cell_out + " is inside --record " + root +
                                ": give the cell a folder of its own, outside the dataset");
  }
  if (!batch::output::HoldsNoResults(root))
    throw std::invalid_argument("--record " + root + " already holds files: give a new or empty folder");
  batch::output::OutputLock lock = batch::output::CreateAndLockOutput(root, "eval");
  batch::output::WriteOutputMarker(root, batch::output::OutputKind::kDataset);
  return lock;
}

std::string DefaultCellDirName(const batch::cell::EvaluationCellConfig& cell, bool one_episode) {
  // A head-still expert's cell must not take the place of the gaze-first one.
  const std::string mode = cell.expert_mode == scenarios::expert::ExpertMode::kGazeFirst
                               ? ""
                               : std::string("-") + scenarios::expert::ToString(cell.expert_mode);
  return batch::cell::CellFolderName(cell, cell.policy + mode, batch::cell::PerturbationsIn::kTail, one_episode);
}

// What the cell's rollouts leave beside its records (--videos, --record), made once the folder
// holds the cell; what they wrote is printed after the summary.
class EvalRollouts {
 public:
  explicit EvalRollouts(const EvalOptions& options) : options_(options) {}

  batch::cell::CellAttachments Attach(const batch::cell::CellPlan& plan,
                                      const std::function<std::filesystem::path()>& folder) {
    // Videos go where the cell is at each write: beside the old cell until the new one is swapped in.
    videos_ = std::make_unique<batch::rollout::CellVideos>(options_.videos, plan.config,
                                                           [folder] { return folder() / "videos"; });
    if (!options_.record.root.empty())
      recording_ = std::make_unique<batch::rollout::CellRecording>(options_.record, plan.config);
    batch::cell::CellAttachments attached;
    attached.sinks = Sinks();
    attached.on_record = [this](const batch::cell::EpisodeRecord& episode) {
      videos_->RecordFinished(episode);
      if (recording_) recording_->RecordFinished(episode);
    };
    attached.records_kept = [this](const std::vector<batch::cell::EpisodeRecord>& resumed) {
      return videos_->RecordsKept(resumed);
    };
    return attached;
  }

  // The summary line, then what the rollouts and the profile wrote beside the records.
  void Finish(const batch::cell::CellResult& result, const std::string& out) {
    namespace fs = std::filesystem;
    std::cout << batch::cell::CellSummaryLine(result) << " -> " << out << "\n";
    if (recording_) {
      recording_->Finish();
      std::cout << "recorded " << recording_->episodes() << " episodes (" << recording_->frames()
                << " frames) as a LeRobot v3.0 dataset -> " << options_.record.root << "\n";
    }
    if (videos_->videos_written() > 0) {
      std::cout << videos_->videos_written()
                << (options_.videos.format == batch::rollout::VideoFormat::kMp4 ? " videos" : " frame folders")
                << " -> " << (fs::path(out) / "videos").string() << "\n";
    }
    if (result.profile) {
      std::cout << batch::cell::FormatCellProfile(*result.profile);
      batch::output::WriteFileAtomically(out + "/profile.json", batch::cell::CellProfileJson(*result.profile));
    }
  }

 private:
  // The videos' and the rollout dataset's sinks, beside the cell's recorder.
  batch::cell::CellSinks Sinks() {
    batch::cell::CellSinks video_sinks = videos_->Sinks();
    batch::cell::CellSinks record_sinks = recording_ ? recording_->Sinks() : nullptr;
    if (!video_sinks && !record_sinks) return nullptr;
    return [video_sinks, record_sinks](const batch::VecEnv& vec_env, const std::vector<std::string>& cameras) {
      std::vector<batch::EpisodeSink*> all;
      for (const batch::cell::CellSinks* part : {&video_sinks, &record_sinks}) {
        if (!*part) continue;
        for (batch::EpisodeSink* sink : (*part)(vec_env, cameras)) all.push_back(sink);
      }
      return all;
    };
  }

  const EvalOptions& options_;
  std::unique_ptr<batch::rollout::CellVideos> videos_;
  std::unique_ptr<batch::rollout::CellRecording> recording_;
};

// What an interrupted cell in `out` kept, and the command that finishes it (Ctrl-C's line).
std::string InterruptedCellLine(const std::filesystem::path& out, const std::string& resume_command) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (fs::exists(batch::output::StagingFolderOf(out), error)) {
    return "interrupted before the new cell recorded an episode: " + out.string() +
           " is as it was; run the command again to replace it";
  }
  if (!fs::exists(out / "cell.json", error)) {
    return "interrupted before " + out.string() + " held a cell: nothing was kept; run the command again";
  }
  return KeptLine(CompleteLines(out / "episodes.jsonl"), out, "the cell", resume_command);
}

// One cell into `out` (batch/cell/cell_folder.h): its records streamed as episodes end (an
// interrupted cell keeps them and --resume continues after them, which `resume_command` does: Ctrl-C
// says so), the summary written last.
batch::cell::CellResult RunCell(const batch::cell::EvaluationCellConfig& cell, const EvalOptions& options, int threads,
                                const std::string& out, const std::string& resume_command) {
  batch::output::RequireUsableOutputPath(out);
  // A served cell's server may declare what its policy needs; the plan adopts it or refuses a flag that contradicts it.
  batch::cell::EvaluationCellConfig declared = cell;
  declared.declared_contract = batch::cell::ReadDeclaredContract(cell);
  batch::cell::CellPlan plan = PlanCellNamingFlags(declared);  // a bad setting must not touch what --out holds
  std::optional<batch::output::OutputLock> record_lock;
  if (!options.record.root.empty()) record_lock.emplace(PrepareRolloutDataset(options.record.root, out));
  for (const std::string& difference : plan.layout_differences) {
    std::cerr << "warning: the served layout differs from the dataset " << cell.observation_dataset << ": "
              << difference << "\n";
  }
  ProgressReporter reporter(stderr, ProgressReporter::StyleFor(stderr));
  batch::cell::CellFolderOptions folder;
  folder.out = out;
  folder.resume = options.resume;
  folder.overwrite = options.overwrite;
  folder.threads = threads;
  if (!options.quiet) {
    folder.progress = [&reporter](int64_t done, int64_t total) { reporter.Update("", done, total); };
  }
  EvalRollouts rollouts(options);
  SetInterruptNotice([out, resume_command] { return InterruptedCellLine(out, resume_command); });
  return batch::cell::RunCellInFolder(
      std::move(plan), folder,
      [&rollouts, &out](const batch::cell::CellPlan& planned, const std::function<std::filesystem::path()>& where) {
        batch::cell::CellAttachments attached = rollouts.Attach(planned, where);
        attached.finish = [&rollouts, &out](const batch::cell::CellResult& result) { rollouts.Finish(result, out); };
        return attached;
      });
}

// Every task of the suite, one cell each in OUT/<task>_<robot>_<split>_<camera>_<policy>_s<seed>, then the
// suite mean as the paper reports it (task average) and pooled over episodes. A task without a
// scripted expert is reported and makes the exit status 1; the others still run.
void RunSuite(batch::cell::EvaluationCellConfig cell, const EvalOptions& options, int threads) {
  std::vector<std::string> tasks;
  for (const scenarios::ScenarioDef* scenario : scenarios::SuiteScenarios(scenarios::ParseSuite(options.suite))) {
    tasks.push_back(scenario->name);
  }
  const std::string base = options.out.empty() ? "results/" + options.suite : options.out;
  double rate_sum = 0.0;
  int cells = 0, successes = 0, episodes = 0;
  std::vector<std::string> failed;
  for (const std::string& task : tasks) {
    cell.task = task;
    try {
      const std::string cell_out = base + "/" + DefaultCellDirName(cell, false);
      // A suite does not resume as a whole: the interrupted cell does, as a cell of its own.
      const std::string resume =
          CommandLineWith({"--overwrite", "--resume"}, {"--suite", "--out"},
                          "--task " + ShellWord(task) + " --out " + ShellWord(cell_out) + " --resume");
      const batch::cell::CellResult result = RunCell(cell, options, threads, cell_out, resume);
      rate_sum += static_cast<double>(result.successes) / static_cast<double>(result.episodes.size());
      successes += result.successes;
      episodes += static_cast<int>(result.episodes.size());
      ++cells;
    } catch (const std::invalid_argument& error) {
      std::cout << task << ": not run: " << ErrorText(error) << "\n";
      failed.push_back(task);
    }
  }
  if (cells > 0) {
    std::printf("%s %s %s policy=%s camera=%s: suite mean over %d tasks %.1f%% (task average), %.1f%% pooled (%d/%d)\n",
                options.suite.c_str(), cell.robot.c_str(), scenarios::ToString(cell.split), cell.policy.c_str(),
                batch::ToString(cell.camera), cells, 100.0 * rate_sum / cells, 100.0 * successes / episodes, successes,
                episodes);
  }
  if (!failed.empty()) {
    std::string names;
    for (const std::string& task : failed) names += (names.empty() ? "" : ", ") + task;
    throw std::runtime_error("suite incomplete: " + names + " not run");
  }
}

void RunEval(const EvalOptions& options) {
  batch::cell::EvaluationCellConfig cell = options.cell;
  if (!options.render_cameras.empty()) cell.render_cameras = batch::ParseCameraList(options.render_cameras);
  if (options.image_size_given) std::tie(cell.image_width, cell.image_height) = ParseImageSize(options.image_size);
  batch::rollout::ValidateEpisodeVideoSettings(options.videos);  // before anything is written
  if (options.videos.episodes > 0 || !options.record.root.empty()) batch::dataset::video::ShowOnlyVideoErrors();
  const int threads = options.threads > 0 ? options.threads : tbb::info::default_concurrency();
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
  if (!options.envs_given) cell.envs = batch::cell::DefaultEnvs(cell.policy, threads);
  if (options.overwrite && options.resume) throw std::invalid_argument("give --overwrite or --resume, not both");
  if (!options.suite.empty()) {
    if (options.task_given) throw std::invalid_argument("give either --task or --suite, not both");
    RunSuite(cell, options, threads);
    return;
  }
  scenarios::FindScenario(cell.task);  // fail fast on an unknown task, before any work
  RunCell(cell, options, threads,
          options.out.empty() ? "results/" + DefaultCellDirName(cell, options.one_episode) : options.out,
          CommandLineWith({"--overwrite", "--resume"}, {}, "--resume"));
}

// --videos and --record: what the cell's rollouts leave beside its records.
void AddRolloutOptions(CLI::App& command, EvalOptions& options) {
  command
      .add_option("--videos", options.videos.episodes,
                  "Film the cell's first N episodes (episode indices from the first of the cell, --episode's with\n"
                  "--episode) as DIR/videos/episode_<i>.mp4 at 20 fps: the policy's cameras tiled with the fixed\n"
                  "camera, the step and the prompt over them, the end held one second with the outcome and GALT.\n"
                  "Rendered apart from the policy's images; the records do not change")
      ->check(IntegerIn(0, 100000000))
      ->capture_default_str();
  command.add_option(
      "--video-cameras", options.video_cameras,
      "For --videos: the cameras shown, comma-separated (head, fixed, left_wrist, right_wrist); default:\n"
      "the policy's cameras under --camera (head or fixed, and the wrists), then the fixed camera");
  command
      .add_option("--video-size", options.video_size,
                  "For --videos: each camera's size in the frame, WIDTHxHEIGHT, even")
      ->capture_default_str();
  command
      .add_option("--video-format", options.video_format,
                  "For --videos: mp4 (H.264), or png (DIR/videos/episode_<i>/frame_<k>.png, one per policy step and\n"
                  "the end)")
      ->capture_default_str();
  command.add_option(
      "--record", options.record.root,
      "Also write the cell's episodes, failed ones too, as a LeRobot v3.0 dataset in DIR (new or empty):\n"
      "per 20 Hz policy step the observation the policy was given and the action it stepped with (its\n"
      "cameras rendered apart at --record-size), and DIR/tavis_rollouts.jsonl with each episode's record");
  command.add_option("--record-cameras", options.record_cameras,
                     "For --record: the cameras stored, comma-separated; default: the policy's cameras under --camera\n"
                     "(the observation contract's head or fixed, and the wrists, for a policy that takes no images)");
  command.add_option("--record-size", options.record_size, "For --record: the stored images' size, WIDTHxHEIGHT")
      ->capture_default_str();
}

// The rollout options read, each refused where what it is for is not given.
void ReadRolloutOptions(const CLI::App& command, EvalOptions& options) {
  for (const char* video_only : {"--video-cameras", "--video-size", "--video-format"}) {
    if (command.count(video_only) > 0 && options.videos.episodes == 0) {
      throw std::invalid_argument(std::string(video_only) + " applies to --videos N (N >= 1), which is not given");
    }
  }
  if (!options.video_cameras.empty()) options.videos.cameras = batch::ParseCameraList(options.video_cameras);
  if (command.count("--video-size") > 0) {
    std::tie(options.videos.tile_width, options.videos.tile_height) = ParseImageSize(options.video_size);
  }
  options.videos.format = batch::rollout::ParseVideoFormat(options.video_format);
  for (const char* record_only : {"--record-cameras", "--record-size"}) {
    if (command.count(record_only) > 0 && options.record.root.empty()) {
      throw std::invalid_argument(std::string(record_only) + " applies to --record DIR, which is not given");
    }
  }
  if (command.count("--record") > 0) {
    if (options.record.root.empty()) throw std::invalid_argument("--record must name a folder, got an empty string");
    if (!options.suite.empty()) throw std::invalid_argument("--record writes one cell's dataset, not a --suite's");
    if (options.resume)
      throw std::invalid_argument("--record cannot --resume: the dataset holds the episodes of one run");
    if (!options.record_cameras.empty()) options.record.cameras = batch::ParseCameraList(options.record_cameras);
    std::tie(options.record.width, options.record.height) = ParseImageSize(options.record_size);
    batch::rollout::ValidateRolloutDatasetSettings(options.record);
  }
}

// The flag a cell setting is given with (cell_settings.h).
const char* FlagOf(const char* setting) { return batch::cell::CellSettingNamed(setting).flag; }

// The eval command once CLI11 has parsed its options: what they imply, then the cell or suite.
void ReadOptionsAndRun(const CLI::App& eval, EvalOptions& options) {
  // Refused rather than ignored: a cell's files must come from the options its command names.
  if (eval.count("--out") > 0 && options.out.empty()) {
    throw std::invalid_argument("--out must name a folder, got an empty string");
  }
  RefuseOptionsOfOtherPolicies(eval, options.cell.policy);
  if (eval.count(FlagOf("episode_start")) > 0) {
    if (!options.suite.empty()) throw std::invalid_argument("--episode runs one cell's episode, not a --suite");
    options.cell.episodes = 1;
    options.cell.first_episode = options.cell.episode_start;
    options.one_episode = true;
  }
  ReadRolloutOptions(eval, options);
  options.cell.observation_keys_given = eval.count(FlagOf("observation_keys")) > 0;
  options.cell.replan_steps_given = eval.count(FlagOf("replan_steps")) > 0;
  options.task_given = eval.count(FlagOf("task")) > 0;
  options.image_size_given = eval.count(FlagOf("image_width")) > 0;
  options.envs_given = eval.count(FlagOf("envs")) > 0;
  RunEval(options);
}

}  // namespace

void RegisterEvalCommand(CLI::App& app) {
  auto options = std::make_shared<EvalOptions>();
  CLI::App* eval =
      app.add_subcommand("eval",
                         "Run one evaluation cell: N episodes of a task with a policy, batched over parallel envs.\n"
                         "Writes DIR/episodes.jsonl (one JSON object per episode) and DIR/summary.json (success\n"
                         "rate with its 95% Wilson interval, wall time, throughput).");
  batch::cell::EvaluationCellConfig& cell = options->cell;
  AddSceneOptions(*eval, {&cell.task, &cell.robot, &cell.split, &cell.seed, &cell.perturbations, &cell.expert_mode,
                          &cell.config_dir});
  AddCellOptions(*eval, cell);
  eval->get_option(FlagOf("episode_start"))->excludes(FlagOf("episodes"));
  eval->add_option(
      "--suite", options->suite,
      "Run every task of a suite instead of one task: " + scenarios::KnownSuites() +
          "; cells go to\n"
          "OUT/<task>_<robot>_<split>_<camera>_<policy>_s<seed> (OUT defaults to results/<suite>), then the\n"
          "suite mean is printed as a task average and pooled over episodes");
  eval->add_option("--threads", options->threads, "Worker threads (0 = all cores; results do not depend on it)")
      ->check(IntegerIn(0, 1024))
      ->capture_default_str();
  // The settings taken in another form than their own option: a comma list, two sizes in one.
  const batch::cell::CellSetting& render_cameras = batch::cell::CellSettingNamed("render_cameras");
  eval->add_option(render_cameras.flag, options->render_cameras, render_cameras.help);
  const batch::cell::CellSetting& image_size = batch::cell::CellSettingNamed("image_width");
  eval->add_option(image_size.flag, options->image_size, image_size.help);
  AddRolloutOptions(*eval, *options);
  eval->add_option("--out", options->out,
                   "Output directory (default results/<task>_<robot>_<split>_<camera>_<policy>_s<seed>)");
  eval->add_flag("--quiet", options->quiet,
                 "No progress (episodes done, rate, ETA; a status line on a terminal, else a line per tenth)");
  eval->add_flag("--overwrite", options->overwrite,
                 "Replace the cell already in --out (only a folder tavis wrote as a cell; the old cell stays\n"
                 "until the new one has recorded its first episode)");
  eval->add_flag("--resume", options->resume,
                 "Finish an interrupted cell in --out (same settings): its complete episodes are kept, the rest run");
  // Every setting of tavis eval comes from its flags: an error naming a setting names the flag.
  eval->callback([options, eval] { RunNamingFlags([&options, &eval] { ReadOptionsAndRun(*eval, *options); }); });
}

}  // namespace tavis::tools

#include "batch/dataset/demo_generation.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/builtin_policies.h"
#include "batch/dataset/demo_recorder.h"
#include "batch/dataset/episode_spool.h"
#include "batch/dataset/lerobot_writer.h"
#include "batch/episode_driver.h"
#include "batch/output/config_identity.h"
#include "batch/output/setting_error.h"
#include "batch/output/settings_difference.h"
#include "batch/perturb/perturbation_catalog.h"
#include "batch/scene/scene_plan.h"
#include "batch/scene_render.h"
#include "batch/vec_env.h"
#include "scenarios/registry.h"

namespace tavis::batch::dataset {
namespace {

using Clock = std::chrono::steady_clock;

// The counts' upper bound (a count beyond it is a mistake, not a dataset).
constexpr double kMaxCount = 1e9;

// Where kept episodes wait, durable, until the dataset is finished (episode_spool.h).
constexpr const char* kSpoolFolder = ".tavis_spool";

double SecondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

std::vector<std::string> StateNames(const kinematics::RobotModel& robot) {
  std::vector<std::string> names;
  for (const kinematics::StateEntry& entry : robot.observation_state) names.push_back(entry.name);
  return names;
}

// The settings that decide what the dataset holds (not envs or threads, which do not).
nlohmann::json Fingerprint(const DemoConfig& config) {
  nlohmann::json fingerprint = {{"tasks", config.tasks},
                                {"robot", config.robot},
                                {"split", scenarios::ToString(config.split)},
                                {"expert_mode", scenarios::expert::ToString(config.expert_mode)},
                                {"episodes", config.episodes},
                                {"max_attempts", config.max_attempts},
                                {"seed", config.seed},
                                {"fps", config.fps},
                                {"expert_hz", config.expert_hz},
                                {"cameras", config.cameras},
                                {"video",
                                 {{"width", config.video.width},
                                  {"height", config.video.height},
                                  {"codec", video::VideoCodecName(config.video.codec)},
                                  {"crf", config.video.crf},
                                  {"gop", config.video.gop},
                                  {"h264_preset", config.video.h264_preset},
                                  {"av1_preset", config.video.av1_preset}}},
                                {"format", ToString(config.version)},
                                {"identity", batch::output::ConfigIdentityJson(config.config_dir, config.robot)}};
  // Only a perturbed recording names its perturbations, so an unperturbed spool resumes as before.
  if (!config.perturbations.empty()) {
    fingerprint["perturbations"] = batch::perturb::PerturbationsJson(
        batch::perturb::ResolvePerturbations(config.config_dir, config.perturbations));
  }
  return fingerprint;
}

// A resumed recording must be the one that was interrupted.
void CheckResumable(const DemoConfig& config, const EpisodeSpool& spool) {
  const nlohmann::json progress = spool.LoadProgress();
  if (progress.is_null()) {
    throw output::SettingsAdvice<std::invalid_argument>(output::SettingKey("resume") + ": " + config.out +
                                                        " holds no interrupted recording (no " + spool.dir() +
                                                        "/progress.json)");
  }
  if (!progress.contains("settings") || !progress["settings"].is_object()) {
    throw std::runtime_error(spool.dir() + "/progress.json: damaged spool file, no \"settings\" object");
  }
  nlohmann::json was = progress["settings"];
  nlohmann::json now = Fingerprint(config);
  // More attempts finish a recording that ran out of them: the episodes already kept stay valid,
  // since episode i draws only on (seed, i).
  was.erase("max_attempts");
  now.erase("max_attempts");
  const std::string differences = batch::output::SettingsDifference(was, now);
  if (!differences.empty())
    throw output::SettingsAdvice<std::invalid_argument>(
        output::SettingKey("resume") + " with other settings than the interrupted recording: " + differences);
}

// Files an interrupted run left unfinished (FILE.partial) outside the spool: they are written again.
void RemovePartialFiles(const std::string& root, const std::string& spool) {
  std::vector<std::filesystem::path> partial;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(root)) {
    const std::string path = entry.path().string();
    if (entry.is_regular_file() && entry.path().extension() == ".partial" && path.rfind(spool, 0) != 0)
      partial.push_back(entry.path());
  }
  for (const std::filesystem::path& path : partial) std::filesystem::remove(path);
}

int64_t DirectoryBytes(const std::string& root) {
  int64_t bytes = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(root)) {
    if (entry.is_regular_file()) bytes += static_cast<int64_t>(entry.file_size());
  }
  return bytes;
}

DatasetLayout DemoLayout(const DemoConfig& config, const kinematics::RobotModel& robot) {
  DatasetLayout layout;
  layout.version = config.version;
  layout.fps = config.fps;
  layout.robot_type = config.robot;
  layout.cameras = config.cameras;
  layout.video = config.video;
  layout.video.fps = config.fps;
  layout.state_names = StateNames(robot);
  for (const std::string& task : config.tasks) layout.tasks.push_back(scenarios::FindScenario(task).class_name);
  return layout;
}

// One recording's run: its settings, where its episodes go and what it reports.
struct DemoSession {
  const DemoConfig& config;
  const DemoProgress& progress;
  const DatasetLayout& layout;
  EpisodeSpool& spool;
  DatasetWriter& writer;
  DemoReport& report;
};

// The spooled episodes, handed to the writer first: each task's count, where it goes on (after its
// last kept one) and the failures before that, so that its report equals an uninterrupted
// recording's.
std::vector<DemoTaskReport> TakeSpooledEpisodes(DemoSession& session) {
  std::vector<DemoTaskReport> tasks(session.config.tasks.size());
  for (int64_t n = 0; n < session.spool.count(); ++n) {
    const SpooledEpisode spooled = session.spool.Load(n);
    DemoTaskReport& task = tasks[static_cast<std::size_t>(spooled.episode.task_index)];
    session.writer.Add(spooled.episode);
    ++task.written;
    task.attempts = spooled.episode.source_episode + 1;
    task.failures = spooled.task_failures_before;
    ++session.report.resumed;
  }
  return tasks;
}

// Records the task's missing episodes in rounds of as many attempts as are still missing, until it
// has its N or has run out of attempts (std::runtime_error; what is kept stays for a resume).
void RecordTask(DemoSession& session, std::size_t task_index, DemoTaskReport task) {
  const DemoConfig& config = session.config;
  scene::ScenePlan plan = scene::PlanScene(scene::SceneOf(config, config.tasks[task_index]));
  const scenarios::ScenarioDef& scenario = *plan.scenario;
  task.task = scenario.name;
  const int cap = config.max_attempts > 0 ? config.max_attempts : 2 * config.episodes + 20;
  const int slots = std::min(config.envs, config.episodes);
  batch::VecEnv vec_env(std::move(plan.model), scenario, config.split, slots, config.seed);
  const int control_hz = static_cast<int>(vec_env.model().physics.control_hz + 0.5);
  const auto expert = std::make_unique<batch::ExpertPolicy>(scenario, vec_env.model(), slots, config.expert_mode,
                                                            control_hz / config.expert_hz);
  DemoRecording recording;
  recording.cameras = config.cameras;
  recording.video = session.layout.video;
  recording.stride = control_hz / config.fps;
  recording.task_index = static_cast<int>(task_index);
  // The round's recorder: it hands episodes over in order, so when it keeps one its failures()
  // are those of this round's episodes before it.
  const DemoRecorder* round_recorder = nullptr;
  const DemoRecorder::Keep keep = [&](RecordedEpisode&& episode) {
    if (task.written >= config.episodes) {
      ++task.surplus;
      return;
    }
    const Clock::time_point write_start = Clock::now();
    std::map<std::string, int64_t> failures_before = task.failures;
    for (const auto& [end, count] : round_recorder->failures()) failures_before[end] += count;
    session.spool.Save(episode, failures_before);
    session.writer.Add(episode);
    session.report.write_s += SecondsSince(write_start);
    ++task.written;
    if (session.progress) session.progress(task.task, task.written, config.episodes);
  };
  // The task's count starts now, with what a resume kept (a progress rate counts from here).
  if (session.progress) session.progress(task.task, task.written, config.episodes);
  while (task.written < config.episodes && task.attempts < cap) {
    const int64_t round = std::min<int64_t>(config.episodes - task.written, cap - task.attempts);
    DemoRecorder recorder(vec_env, recording, task.attempts, keep);
    round_recorder = &recorder;
    batch::EpisodeDriver driver(vec_env, *expert, round, task.attempts);
    driver.AddSink(recorder);
    if (config.lock_step) driver.RequireLockStep();
    driver.Run();
    task.attempts += round;
    for (const auto& [end, count] : recorder.failures()) task.failures[end] += count;
    session.report.render_s += recorder.times().render_s;
    session.report.encode_s += recorder.times().encode_s;
    session.report.capture_s += recorder.times().capture_s;
  }
  session.report.tasks.push_back(task);
  if (task.written < config.episodes) {
    const std::string max_attempts = output::SettingKey("max_attempts");
    throw output::SettingsAdvice<std::runtime_error>(
        "task " + task.task + ": only " + std::to_string(task.written) + " of " + std::to_string(config.episodes) +
        " episodes succeeded in " + std::to_string(task.attempts) + " attempts (" + max_attempts +
        "); the episodes recorded so far are kept: " + output::SettingKey("resume") + " with a larger " + max_attempts +
        " finishes the dataset");
  }
}

}  // namespace

void ValidateDemoConfig(const DemoConfig& config) {
  if (config.tasks.empty()) throw std::invalid_argument("no task to record");
  for (const std::string& task : config.tasks) {
    if (scenarios::FindScenario(task).make_expert == nullptr) {
      throw std::invalid_argument("task '" + task + "' has no scripted expert to record");
    }
  }
  // Each setting named by its key in the spool's settings (Fingerprint); `tavis demos` names the
  // flag that gave it.
  output::CheckSettingRange("episodes", config.episodes, output::SettingRange::Between(1, kMaxCount));
  output::CheckSettingRange("max_attempts", config.max_attempts, output::SettingRange::Between(0, kMaxCount));
  if (config.max_attempts > 0 && config.max_attempts < config.episodes) {
    throw output::SettingError("max_attempts", std::to_string(config.max_attempts) + " is below episodes " +
                                                   std::to_string(config.episodes) + " (0: 2 x episodes + 20)");
  }
  output::CheckSettingRange("envs", config.envs, output::SettingRange::Between(1, kMaxCount));
  output::CheckSettingRange("fps", config.fps, output::SettingRange::OneOf({60, 20}));
  output::CheckSettingRange("expert_hz", config.expert_hz, output::SettingRange::OneOf({60, 20}));
  batch::CameraSettings cameras;
  cameras.cameras = config.cameras;
  cameras.width = config.video.width;
  cameras.height = config.video.height;
  batch::ValidateCameraSettings(cameras);
  for (const std::string& camera : config.cameras) CameraVideoKey(camera);
  for (const std::string& choice : config.perturbations) batch::perturb::ParsePerturbationChoice(choice);
  video::VideoSettings video = config.video;
  video.fps = config.fps;
  video::ValidateVideoSettings(video, "video");
}

DemoReport GenerateDemos(const DemoConfig& config, const DemoProgress& progress) {
  ValidateDemoConfig(config);
  // The first task's scene, planned before anything is written: a bad robot file or perturbation
  // fails here, and the dataset's state names are its robot's.
  const scene::ScenePlan first = scene::PlanScene(scene::SceneOf(config, config.tasks.front()));
  const Clock::time_point start = Clock::now();
  const DatasetLayout layout = DemoLayout(config, first.model.robot);
  EpisodeSpool spool(config.out + "/" + kSpoolFolder, layout);
  if (config.resume) {
    CheckResumable(config, spool);
    RemovePartialFiles(config.out, spool.dir());
  } else if (spool.count() > 0) {
    throw output::SettingsAdvice<std::invalid_argument>(
        config.out + " holds an interrupted recording: " + output::SettingKey("resume") + " it or " +
        output::SettingKey("overwrite") + " it");
  }
  spool.SaveProgress({{"settings", Fingerprint(config)}});
  const std::unique_ptr<DatasetWriter> writer = MakeDatasetWriter(config.out, layout);
  DemoReport report;
  DemoSession session{config, progress, layout, spool, *writer, report};
  const std::vector<DemoTaskReport> spooled = TakeSpooledEpisodes(session);
  for (std::size_t task_index = 0; task_index < config.tasks.size(); ++task_index) {
    RecordTask(session, task_index, spooled[task_index]);
  }
  const Clock::time_point finish_start = Clock::now();
  writer->Finish();
  spool.Remove();
  report.write_s += SecondsSince(finish_start);
  report.episodes = writer->episodes();
  report.frames = writer->frames();
  report.bytes = DirectoryBytes(config.out);
  report.wall_s = SecondsSince(start);
  report.simulate_s =
      std::max(0.0, report.wall_s - report.render_s - report.encode_s - report.capture_s - report.write_s);
  return report;
}

}  // namespace tavis::batch::dataset

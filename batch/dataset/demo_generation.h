// `tavis demos`: scripted-expert demonstrations of one task or a whole suite written as one
// LeRobot dataset (docs/architecture.md, Design 10). Each task runs its expert batched over env slots; successful
// episodes are kept in episode order until the task has its N episodes, failures are counted and
// never written, and a task that cannot reach N within its attempt cap is an error naming it.
// Episode i of a task draws its randomness from (seed, i), so the same command writes the same
// dataset with any thread count.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "batch/dataset/lerobot_features.h"
#include "batch/dataset/video/video_settings.h"
#include "scenarios/expert/expert_mode.h"
#include "scenarios/split.h"

namespace tavis::batch::dataset {

struct DemoConfig {
  std::vector<std::string> tasks;  // one dataset holds every task's episodes, tasks in this order
  std::string robot = "gr1t2";
  scenarios::Split split = scenarios::Split::kId;
  // How the expert's head leads: gaze-first (the reference's teleoperators), or head-still.
  scenarios::expert::ExpertMode expert_mode = scenarios::expert::ExpertMode::kGazeFirst;
  int episodes = 100;    // written per task
  int max_attempts = 0;  // per task; 0: 2 * episodes + 20
  uint64_t seed = 0;
  int envs = 8;  // parallel env slots
  // Steps the slots lock-step rather than each on its own thread (the dataset is the same; tests
  // compare the two schedules).
  bool lock_step = false;
  int fps = 60;  // 60 (the reference's) or 20
  // How often the expert's commanded action may change: 60 Hz (every control tick, the
  // reference's teleoperation rate) or 20 Hz (held for three ticks, as a learned 20 Hz policy
  // acts: served back at 20 Hz, the action rows reproduce the episode; batch::ExpertPolicy).
  int expert_hz = 60;
  std::vector<std::string> cameras = {"head", "fixed", "left_wrist", "right_wrist"};
  video::VideoSettings video;  // size and codec; fps is set from `fps`
  DatasetVersion version = DatasetVersion::kV30;
  std::string config_dir;  // holds robots/*.yaml
  // Perturbation levels, "AXIS:LEVEL" each (batch/perturb/perturbation_catalog.h): every episode is
  // recorded under them, so a dataset can be randomised along an axis. Empty: the base scene.
  std::vector<std::string> perturbations;
  std::string out;
  // Continue an interrupted recording into `out` after the last episode it had kept (they are
  // kept in OUT/.tavis_spool until the dataset is finished). The settings must be the same.
  bool resume = false;
};

struct DemoTaskReport {
  std::string task;
  int64_t written = 0;
  int64_t attempts = 0;
  std::map<std::string, int64_t> failures;  // by how the episode ended
  int64_t surplus = 0;                      // successes past N in the last round, not written
};

struct DemoReport {
  std::vector<DemoTaskReport> tasks;
  int64_t resumed = 0;  // episodes taken over from an interrupted recording
  int64_t episodes = 0;
  int64_t frames = 0;
  int64_t bytes = 0;  // of the dataset's files
  double wall_s = 0;
  // Where the time went: the recorder's rendering, encoding and capture, the writer, and the
  // rest (simulation and the expert).
  double render_s = 0, encode_s = 0, capture_s = 0, write_s = 0, simulate_s = 0;
};

// Called with (task, written, wanted) as a task starts (written: what a resume kept) and after each
// kept episode.
using DemoProgress = std::function<void(const std::string&, int64_t, int64_t)>;

// Throws std::invalid_argument naming the first bad setting of `config` (tasks, counts, fps,
// cameras, video size and codec); touches no file, so a command can check before preparing --out.
void ValidateDemoConfig(const DemoConfig& config);

// Throws std::invalid_argument / configs::ConfigError for bad settings (before anything is
// written) or a resume whose settings differ (naming them), std::runtime_error naming the task
// when its attempt cap is reached first, and std::runtime_error naming the file on an I/O failure.
DemoReport GenerateDemos(const DemoConfig& config, const DemoProgress& progress = nullptr);

}  // namespace tavis::batch::dataset

// An evaluation cell: (task, robot, split, seed, policy) x N episodes run over M parallel env
// slots. Episode i always gets the randomness of (seed, i), so a cell's records are identical
// for any thread count and any number of slots.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "engine/batch_state.h"
#include "kinematics/action.h"
#include "kinematics/galt.h"
#include "scenarios/split.h"

namespace tavis::batch {

struct EvaluationCellConfig {
  std::string task = "clutter-pick-cube";
  std::string robot = "gr1t2";
  scenarios::Split split = scenarios::Split::kId;
  std::string policy = "expert";
  std::string actions_file;  // for the replay policy
  int episodes = 96;
  int envs = 32;  // parallel env slots
  uint64_t seed = 0;
  std::string config_dir;  // holds robots/*.yaml
  // Cameras rendered on every policy tick even if the policy does not consume them (throughput
  // runs); the policy's own cameras() are always rendered. Names from SceneCameraNames().
  std::vector<std::string> render_cameras;
  int image_width = 640;  // resolution of every rendered camera (the reference's 640 x 480)
  int image_height = 480;
};

struct EpisodeRecord {
  int64_t episode = 0;
  bool success = false;
  engine::EpisodeEnd end = engine::EpisodeEnd::kRunning;
  int length_steps = 0;          // policy-rate (20 Hz) steps, as the reference counts them
  int length_control_ticks = 0;  // 60 Hz control ticks
  int solver_messages = 0;       // ODE solver messages (degenerate contacts), for diagnosis
  std::vector<kinematics::Action> actions;  // commanded action of every control tick
  // GALT of the commanded actions at the policy's action rate, for successful episodes only
  // (the reference computes it for those).
  std::optional<kinematics::GaltResult> galt;
  // The same at the 20 Hz policy rate, for a policy acting faster (the scripted experts at 60 Hz),
  // as the paper's validation table reports both.
  std::optional<kinematics::GaltResult> galt_policy_rate;
};

struct CellResult {
  EvaluationCellConfig config;
  std::vector<EpisodeRecord> episodes;  // ordered by episode index
  int successes = 0;
  double wall_s = 0.0;
  int64_t control_ticks = 0;  // env control ticks simulated, for throughput
  double galt_fps = 0.0;      // rate of the action samples GALT was computed on
  double galt_policy_rate_fps = 0.0;  // 0 when the policy acts at the policy rate
  std::vector<std::string> rendered_cameras;  // the policy's cameras, then the extra render_cameras
  int64_t rendered_images = 0;                // env-camera images rendered
};

// Called after each finished episode with (finished, total).
using ProgressCallback = std::function<void(int, int)>;

class VecEnv;

// Hands episodes 0..total-1 to env slots in index order. Episode i draws its randomness from
// (seed, i) whichever slot runs it, so refilling slots serially in slot order keeps a run's
// results independent of the thread count and of the number of slots.
class EpisodeDealer {
 public:
  explicit EpisodeDealer(int64_t total) : total_(total) {}
  // Resets `slot` with the next episode and returns true, or releases the slot when none is left.
  bool Deal(VecEnv& env, int slot);

 private:
  int64_t total_ = 0;
  int64_t next_ = 0;
};

// Throws std::invalid_argument / configs::ConfigError for bad settings, and std::runtime_error
// naming the episode, action entry and value if the policy produced a non-finite action.
CellResult RunEvaluationCell(const EvaluationCellConfig& config, const ProgressCallback& progress = nullptr);

}  // namespace tavis::batch

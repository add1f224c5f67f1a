// An evaluation cell: (task, robot, split, camera protocol, seed, policy) x N episodes run over M parallel env
// slots. Episode i always gets the randomness of (seed, i), so a cell's records are identical
// for any thread count and any number of slots.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "batch/cell/cell_plan.h"
#include "batch/cell/cell_profile.h"
#include "batch/cell/cell_settings.h"
#include "batch/cell/episode_recorder.h"
#include "batch/episode_driver.h"
#include "batch/remote/remote_policy.h"

namespace tavis::batch::cell {

struct CellResult {
  EvaluationCellConfig config;  // as run: the image size resolved
  int render_width = 0;         // the cameras' rendered size (letterboxed into the image size)
  int render_height = 0;
  std::vector<EpisodeRecord> episodes;  // the episodes run, ordered by episode index
  int successes = 0;
  int envs = 0;  // the env slots that ran (at most the episodes to run)
  double wall_s = 0.0;
  int64_t control_ticks = 0;                  // env control ticks simulated, for throughput
  double galt_fps = 0.0;                      // rate of the action samples GALT was computed on
  double galt_policy_rate_fps = 0.0;          // 0 when the policy acts at the policy rate
  std::vector<std::string> rendered_cameras;  // the policy's cameras, then the extra render_cameras
  int64_t rendered_images = 0;                // env-camera images rendered
  // A served policy's requests; its episodes' actions are kept for --policy replay
  // (EpisodeRecord::replay_actions).
  std::optional<remote::RequestTimings> requests;
  std::vector<remote::Value> server_metadata;  // each server's metadata message
  std::string observation_keys_source;         // the request layout's preset, file or dataset
  // How the served layout differs from observation_dataset's (empty: it does not, or none given).
  std::vector<std::string> layout_differences;
  std::optional<CellProfile> profile;  // with config.profile
  bool per_slot = false;               // run on the driver's per-slot schedule (RunsPerSlot)
};

// Policy names a cell accepts, for --help texts and errors: the built-in ones and "openpi".
std::string CellPolicyNames();

// True if the cell's episodes run on the episode driver's per-slot schedule: a built-in policy
// (each env decided on its own; its cameras, rendered or not, are drawn per slot), unless a sink
// the caller adds needs the common tick (episode videos). Such a cell keeps every thread busy
// until its last episodes.
bool RunsPerSlot(const EvaluationCellConfig& config);

// The --envs a cell gets when none is given: 32, and for a served policy (lock-step, a batch per
// request) 6 per thread when that is more (96 on 16 threads), so that each tick's wait for the
// slowest env and the server is shared by more envs.
int DefaultEnvs(const std::string& policy, int threads);

// Called with each episode's record as soon as it and every earlier episode have ended.
using RecordCallback = std::function<void(const EpisodeRecord&)>;

// Further sinks a caller plugs into the cell's driver beside its recorder (episode videos, a
// rollout dataset), made once the env exists; `policy_cameras` are the cameras the policy sees
// under the camera protocol (empty for one that takes no images). The sinks watch; what they do
// must not change the records.
using CellSinks =
    std::function<std::vector<EpisodeSink*>(const VecEnv& vec_env, const std::vector<std::string>& policy_cameras)>;

// Runs the plan's episodes from plan.config.first_episode on. Throws std::runtime_error naming the
// server when a served policy's server is unreachable or fails. An unusable action ends only its
// episode (invalid_action, recorded with the entry and the reason).
CellResult RunEvaluationCell(const CellPlan& plan, const ProgressCallback& progress = nullptr,
                             const RecordCallback& on_record = nullptr, const CellSinks& sinks = nullptr);
// PlanCell(config), then runs it.
CellResult RunEvaluationCell(const EvaluationCellConfig& config, const ProgressCallback& progress = nullptr,
                             const RecordCallback& on_record = nullptr, const CellSinks& sinks = nullptr);

}  // namespace tavis::batch::cell

// A cell's settings resolved and checked once: PlanCell reads the robot file (and a served
// policy's key file) once, builds from it and records its identity from the same bytes, finds the task,
// resolves the perturbation levels and a served policy's request layout, and decides the image
// and render sizes, the cameras to render and what the recorder keeps, without running anything.
// RunEvaluationCell executes a plan; the commands, the sweep and the records (cell.json) use the
// plan rather than deriving these again from the settings.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/cell/cell_settings.h"
#include "batch/cell/episode_recorder.h"
#include "batch/perturb/perturbation_catalog.h"
#include "batch/policy_kinds.h"
#include "batch/remote/observation_keys.h"
#include "engine/world_model.h"
#include "scenarios/scenario.h"

namespace tavis::batch::cell {

struct CellPlan {
  EvaluationCellConfig config;  // as given (cell.json records it so), first_episode included
  const scenarios::ScenarioDef* scenario = nullptr;
  // The robot (its file read once) in the task's scene, the perturbation levels applied.
  engine::WorldModel model;
  PolicyKind policy = PolicyKind::kExpert;
  std::vector<perturb::PerturbationLevel> perturbations;  // the levels chosen, as their files say
  // What cell.json records of the files behind the settings (output::ConfigIdentityJson), from
  // the bytes the plan read.
  nlohmann::json identity;
  // A served policy's request layout, and how it differs from observation_dataset's (one line
  // each; empty when it does not or no dataset is named).
  std::optional<remote::ObservationKeys> keys;
  std::vector<std::string> layout_differences;
  // The policy's images, and the cameras' rendered size (letterboxed into it for a served layout
  // that says so).
  int image_width = 0;
  int image_height = 0;
  int render_width = 0;
  int render_height = 0;
  // The cameras the policy sees under the camera protocol, and every camera rendered: those
  // first (its images keep their order), then the extra render_cameras.
  std::vector<std::string> policy_cameras;
  std::vector<std::string> cameras;
  int control_ticks_per_action = 1;  // how long the policy holds each action
  RecordSettings record;             // what the cell's recorder keeps

  // One past the cell's last episode.
  int64_t end_episode() const { return config.episode_start + config.episodes; }
  // Runs the episodes from `first` on (a resumed cell's next one); throws std::invalid_argument
  // unless it is in [episode_start, end_episode()].
  void ContinueFrom(int64_t first);
};

// Checks every setting (the table's ranges and scopes, the task, the robot file, the policy, the
// cameras and sizes, the perturbation levels, a served policy's keys and dataset) and resolves
// them. Throws output::SettingError naming a bad setting by its key, std::invalid_argument /
// configs::ConfigError naming a bad value or file.
CellPlan PlanCell(const EvaluationCellConfig& config);

// Each server's URL, checked before any folder is touched or any server is asked (PlanCell does,
// and what reads a server's declared contract before planning); throws naming the setting.
void CheckServerUrls(const EvaluationCellConfig& config);

// What cell.json records of the files behind the settings: the robot file, a served policy's key
// file and the program version (output::ConfigIdentityJson), reading them; a plan has it already.
nlohmann::json CellIdentityJson(const EvaluationCellConfig& config);

// What a cell's recorder keeps for a policy acting every `hold_ticks` control ticks: GALT at that
// rate (and at the 20 Hz policy rate for a faster policy) under the head protocol, the served
// policy's actions for replay, every action with config.keep_actions.
RecordSettings RecordSettingsFor(const EvaluationCellConfig& config, int hold_ticks,
                                 const engine::PhysicsSettings& physics, bool served);

}  // namespace tavis::batch::cell

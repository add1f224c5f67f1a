// Joint-target trajectories of scripted-expert episodes, recorded from our engine so that a peer
// engine can be driven through exactly the same commands: for each episode the reset state
// (joint positions, object poses) and, per 60 Hz control tick, the arm joint targets the IK
// produced and the gripper commands.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "engine/world_model.h"

namespace tavis::peer {

struct EpisodeTrajectory {
  std::vector<double> q0;               // (num_joints) joint positions after the reset
  std::vector<double> object_pose0;     // (num_objects x 7) x, y, z, qw, qx, qy, qz
  std::vector<uint8_t> object_enabled;  // (num_objects)
  std::vector<double> q_target;         // (ticks x num_joints)
  std::vector<double> gripper_command;  // (ticks x 2) left, right in [-1, 1]
  bool success = false;
};

struct ExpertTrajectories {
  engine::WorldModel model;
  int ticks = 0;  // every episode is padded to this many ticks by holding its last command
  std::vector<EpisodeTrajectory> episodes;
};

// Runs `episodes` expert episodes (0 .. episodes-1, seed 0, `id` split) of `task` with `robot`
// from `config_dir` in one VecEnv and records them for `ticks` control ticks.
ExpertTrajectories RecordExpertTrajectories(const std::string& config_dir, const std::string& task,
                                            const std::string& robot, int episodes, int ticks);

}  // namespace tavis::peer

// The physics of a TAVIS world rebuilt in MuJoCo for the peer benchmark: the same kinematic tree
// (arm links on hinges, fingers on sliders), masses and body inertias, collision shapes, contact
// filtering, friction and rates, with the arms and fingers driven by the same velocity servos
// toward the recorded joint targets as our ODE motors. MuJoCo types stay in the .cc file.
#pragma once

#include <memory>
#include <string>

#include "bench/peer/expert_trajectories.h"

namespace tavis::peer {

// The MJCF text of the world (written next to the results so a reader can inspect it).
std::string PhysicsMjcf(const engine::WorldModel& model, bool sparse_jacobian);

// One compiled MuJoCo model and one mjData per env.
class MujocoPhysics {
 public:
  MujocoPhysics(const engine::WorldModel& model, int num_envs, bool sparse_jacobian);
  ~MujocoPhysics();
  MujocoPhysics(const MujocoPhysics&) = delete;
  MujocoPhysics& operator=(const MujocoPhysics&) = delete;

  // Puts env `env` in the episode's reset state.
  void Reset(int env, const EpisodeTrajectory& episode);
  // One 60 Hz control tick (substeps_per_control physics steps) toward the episode's tick `tick`.
  void StepTick(int env, const EpisodeTrajectory& episode, int tick);
  // World position of an object's body (a sanity check that both engines did the same task).
  void ObjectPosition(int env, int object, double* xyz) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tavis::peer

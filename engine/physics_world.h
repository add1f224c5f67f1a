// One env's rigid-body world (ODE): the robot's arms as articulated bodies driven by joint
// motors, parallel-jaw fingers on slider motors, the movable objects and the static scene.
// The neck carries only the head and its camera, so it is not simulated here: the VecEnv
// servos it kinematically. ODE types stay inside the implementation.
#pragma once

#include <array>
#include <cstdint>
#include <memory>

#include "engine/world_model.h"

namespace tavis::engine {

class PhysicsWorld {
 public:
  // `model` must outlive the world.
  explicit PhysicsWorld(const WorldModel& model);
  ~PhysicsWorld();
  PhysicsWorld(const PhysicsWorld&) = delete;
  PhysicsWorld& operator=(const PhysicsWorld&) = delete;

  // Places the arms at joint positions q (num_joints; neck entries ignored) at rest, fingers
  // open, and clears contacts and the message count. The step is ODE's exact (Dantzig LCP)
  // solver, which carries no state between steps, so an episode's physics depends only on its
  // own inputs, never on what the world ran before.
  void ResetRobot(const double* q);
  // Places an object at rest; a disabled object takes no part in the simulation.
  void SetObject(int object, const Vec3& position, const Quat& orientation, bool enabled);

  // Advances `substeps` physics steps with arm joint motors servoing toward q_target
  // (num_joints) and fingers toward gripper_command (left, right in [-1, 1]). Returns false if
  // the world blew up (NaN or runaway speed); the world must then be reset.
  bool Step(const double* q_target, const std::array<double, 2>& gripper_command, int substeps);

  // Writes arm joint positions into q (num_joints; other entries untouched), the gripper gaps,
  // and object poses (num_objects x 7) and velocities (num_objects x 6). Kinematic objects keep
  // the pose the task gave them and read as at rest.
  void ReadState(double* q, double* gripper_gap, double* object_pose, double* object_velocity) const;

  // Solver messages (degenerate contact sets) since the last reset.
  int solver_messages() const;

  // Friction of a material, changeable for tests (e.g. a frictionless grasp).
  void SetFriction(Material material, double friction);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tavis::engine

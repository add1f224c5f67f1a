// The immutable description shared by all envs of a batch: robot, movable objects, static
// scene parts, contact materials and clock rates. Scenarios fill it once (Layout); the step
// only reads it.
#pragma once

#include <string>
#include <vector>

#include "engine/episode_perturbation.h"
#include "engine/render_perturbation.h"
#include "kinematics/robot_model.h"
#include "kinematics/shape.h"

namespace tavis::engine {

// Contact material: the friction of a pair is the average of both (PhysX's default combine).
enum class Material : int { kDefault = 0, kTable, kObject, kFingerPad, kRobot, kCount };

struct MaterialTable {
  double friction[static_cast<int>(Material::kCount)] = {0.5, 0.5, 0.5, 1.5, 0.5};
  double Friction(Material m) const { return friction[static_cast<int>(m)]; }
  double& Friction(Material m) { return friction[static_cast<int>(m)]; }
};

// Dynamic objects are simulated; kinematic ones (a cue card, a signal light, a box's walls)
// stay where the task's reset puts them and only collide if `collides`.
enum class ObjectMotion : uint8_t { kDynamic, kKinematic };

// A rigid object whose pose is part of the batch state (YCB stand-in or task primitive).
struct ObjectSpec {
  std::string name;
  Shape shape;
  double mass = 0.0;
  Material material = Material::kObject;
  std::string appearance;  // palette name used by the renderer
  ObjectMotion motion = ObjectMotion::kDynamic;
  bool collides = true;
  // An extra object a perturbation put in the scene (not part of the task): the appearance axis's
  // `distractors` texture applies to these.
  bool distractor = false;
};

// A static part of the scene (table top, screen, shelf board): collides, never moves.
struct StaticPart {
  std::string name;
  Shape shape;
  RigidTransform X_WS = RigidTransform::Identity();
  Material material = Material::kTable;
  std::string appearance;
  bool collides = true;  // cue cards and lights are visual only
};

struct PhysicsSettings {
  // 3 ODE substeps per control tick. ODE's exact LCP is most of a cell's time and runs once per
  // substep; below 180 Hz an arm point could move farther in one substep than the kinematic-arm
  // margin (docs/fidelity.md, "Physics rate").
  double substep_hz = 180.0;
  double control_hz = 60.0;
  double policy_hz = 20.0;
  double episode_length_s = 20.0;
  double gravity = -9.81;
  double contact_erp = 0.2;
  double contact_cfm = 1e-6;
  int max_contacts_per_pair = 6;
  // Speeds above these mark an env as blown up (failed with a reason, then reset).
  double runaway_linear_speed = 20.0;
  double runaway_angular_speed = 200.0;

  int substeps_per_control() const { return static_cast<int>(substep_hz / control_hz + 0.5); }
  int controls_per_policy() const { return static_cast<int>(control_hz / policy_hz + 0.5); }
  int max_control_steps() const { return static_cast<int>(episode_length_s * control_hz + 0.5); }
};

// The scene's distant (shadow-casting) light, reference 2.1; multi-shelf-scan overrides it.
// The dome light is the same everywhere.
struct SceneLighting {
  Vec3 distant_direction = Vec3(-0.342, -0.321, -0.883);  // direction of travel
  double distant_intensity = 2000.0;
};

struct WorldModel {
  kinematics::RobotModel robot;
  std::vector<ObjectSpec> objects;
  std::vector<StaticPart> static_parts;
  MaterialTable materials;
  SceneLighting lighting;
  PhysicsSettings physics;
  // What the cell's perturbations change in the views (identity: none); read by renderers only.
  RenderPerturbation view_perturbation;
  // What the cell's distractors, language and runtime levels change in its episodes (none: nothing).
  EpisodePerturbation episode_perturbation;

  int num_objects() const { return static_cast<int>(objects.size()); }
  // The task's own objects come first (its layout); the distractors axis appends its objects after
  // them. A task's reset draws for its own objects only, so its draws do not depend on them.
  int num_task_objects() const { return num_objects() - episode_perturbation.num_distractor_objects(); }
  int ObjectIndex(const std::string& name) const;  // throws std::out_of_range naming it
};

}  // namespace tavis::engine

// A task, declared: its name and suite, the objects its information sits in, its success rule,
// the cameras it blacks out, its facts for the record, its prompt's paraphrases and its gaze
// anchors, and the hooks
// that lay out, reset and advance its scene, phrase its prompt and make its scripted expert; its
// own per-env variables are a struct of its own (task_state.h). Everything outside scenarios/
// learns a task's facts from here, never from its name. Hooks act on one env; the VecEnv runs
// them over env ranges in parallel, so they must only touch that env's rows of the BatchState.
#pragma once

#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "engine/batch_state.h"
#include "engine/world_model.h"
#include "kinematics/action.h"
#include "scenarios/expert/expert_mode.h"
#include "scenarios/gaze_anchor.h"
#include "scenarios/split.h"
#include "scenarios/stage.h"
#include "scenarios/suite.h"
#include "scenarios/support_zone.h"

namespace tavis::scenarios {

// A privileged scripted policy for one task, stepping at the control rate. One instance serves
// a whole batch; per-env memory lives inside it, indexed by env.
class Expert {
 public:
  // Where the expert is looking: the object its head fixates (-1: none, or a scan point), and
  // whether the cameras it reads that object with have come to rest on it (the head settled; in
  // a peek, both wrist cameras at their peek poses). The visibility audit samples this.
  struct Gaze {
    int object = -1;
    bool settled = false;
  };

  virtual ~Expert() = default;
  virtual void Reset(const engine::WorldModel& model, const engine::BatchState& state, int env) = 0;
  virtual void Act(const engine::WorldModel& model, const engine::BatchState& state, int env,
                   kinematics::Action& action) = 0;
  virtual Gaze gaze(const engine::BatchState& state, int env) const = 0;
  // True once the expert has given up on env's episode: it holds still from then on.
  virtual bool gave_up(int env) const = 0;
};

// The reference's success terms (reference 1.5): the episode's target lifted above a world
// height, or pulled out of a shelf toward the robot past a world x, and nearly at rest.
struct SuccessRule {
  enum class Kind { kLiftAbove, kPullOutPast };
  Kind kind = Kind::kLiftAbove;
  double threshold_m = 0.0;    // world z (kLiftAbove: above it) or x (kPullOutPast: below it)
  double max_speed_mps = 1.0;  // the target's linear speed must be below this
  // Optional: the task's go signal (wait-then-act's green light); success counts only once it is given.
  bool (*after_go)(const engine::BatchState& state, int env) = nullptr;
};

SuccessRule LiftAbove(double height_m);
SuccessRule PullOutPast(double x_m);

// The stages of a pick (stage.h): the cue fixated within 0.15 rad of the best fixation the
// neck's limits allow (a task with a cue: the cue card, the signal light), the target approached
// within 5 cm, grasped, and lifted (a pull-out rule: pulled) 3 cm. Keys: cue_fixated,
// target_approached, target_grasped, target_lifted or target_pulled.
std::vector<StageDef> PickStages(const SuccessRule& success, const std::string& cue = "");

// One fact of an episode besides its target object, for its record: a key and its value, a text
// or a whole number (conditional-pick's {"side", "left"}, multi-shelf-scan's {"shelf", 2}). The
// record writes and reads them as they are, so a task's facts are its own; "object" and
// "moved_tick" are the record's.
struct TargetFact {
  std::string key;
  std::variant<std::string, int> value;

  bool operator==(const TargetFact& other) const { return key == other.key && value == other.value; }
};
using TargetFacts = std::vector<TargetFact>;

// A task's paraphrases of its prompt under one language perturbation level (docs/perturbations.md):
// the level, by its name in configs/perturbations/language.yaml, falls back to them when it gives
// the task none of its own. "{object}" stands for the episode's target.
struct LevelParaphrases {
  std::string level;
  std::vector<std::string> texts;
};

struct ScenarioDef {
  std::string name;  // e.g. "clutter-pick-cube"
  // The reference's task class ("ClutterPickCubeTask"): LeRobot's `task` in its datasets.
  std::string class_name;
  Suite suite = Suite::kTavisHead;
  SuccessRule success;
  // Adds the task's objects and static parts to the world (once per batch).
  void (*layout)(engine::WorldModel& model) = nullptr;
  // Draws a new episode for `env` from its task stream (state.task_rng[env]): object poses,
  // enabled flags and colours, the task variables (state.task[env], the target always) and the
  // task's own (task_state.h).
  void (*reset)(const engine::WorldModel& model, Split split, engine::BatchState& state, int env) = nullptr;
  // Optional: advances the task's own clock once per control tick, after physics and before the
  // success check (wait-then-act's light turning green).
  void (*update)(const engine::WorldModel& model, engine::BatchState& state, int env) = nullptr;
  // The instruction the policy receives for the env's episode (fixed at reset).
  const char* (*prompt)(const engine::BatchState& state, int env) = nullptr;
  // Null for a task without a scripted expert; `mode`: how its head leads (expert_mode.h).
  std::unique_ptr<Expert> (*make_expert)(const engine::WorldModel& model, int num_envs,
                                         expert::ExpertMode mode) = nullptr;
  // Objects besides the target whose sight decides the episode, by model name (the cue card, the
  // signal light): the visibility audit measures them with the target.
  std::vector<std::string> cue_objects;
  // Cameras whose image the policy receives all black (the camera still moves).
  std::vector<std::string> black_cameras;
  // The steps a successful episode passes, in order (stage.h); recorded per episode.
  std::vector<StageDef> stages;
  // Optional: the task's facts of the env's episode (fixed at reset) besides its target.
  TargetFacts (*target_facts)(const engine::BatchState& state, int env) = nullptr;
  // The task's paraphrases of its prompt, per language level (above); a level that gives none and
  // finds none here is refused when its file is read.
  std::vector<LevelParaphrases> paraphrases = {};
  // The scene perturbation axes (docs/perturbations.md), of the env's episode right after its
  // reset. distractor_zones: where extra objects may stand without blocking the task: areas of
  // its supports that no hand, held object or line of sight to a cue the task needs passes through.
  // target_zones: where the runtime axis may move the target: the area of its support the
  // scripted expert reaches (the widest split's placement area). Null: the task refuses the axis.
  std::vector<SupportZone> (*distractor_zones)(const engine::BatchState& state, int env) = nullptr;
  std::vector<SupportZone> (*target_zones)(const engine::BatchState& state, int env) = nullptr;
  // The lead times its records measure from a fixation to an action event (gaze_anchor.h), in the
  // order the records and tables list them.
  std::vector<GazeAnchor> gaze_anchors = {};

  // True on a control tick the success rule holds for the env's episode.
  bool Succeeded(const engine::BatchState& state, int env) const;
};

}  // namespace tavis::scenarios

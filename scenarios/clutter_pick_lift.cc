#include "scenarios/clutter_pick_lift.h"

#include <array>

#include "engine/object_catalog.h"
#include "scenarios/clutter_pick_cube.h"
#include "scenarios/expert/pick_expert.h"
#include "scenarios/object_placement.h"
#include "scenarios/tabletop.h"

namespace tavis::scenarios {
namespace {

// Reference 4.4, in TAVIS_HEAD_OBJECT_NAMES order.
constexpr TargetPrompts kPrompts = {{
    {"Pick up the tomato soup can and lift it.", "Grasp the soup can and hold it up.",
     "Lift the red soup can off the table."},
    {"Pick up the potted meat can and lift it.", "Grasp the can of spam and hold it up.",
     "Lift the meat can off the table."},
    {"Pick up the tuna fish can and lift it.", "Grasp the tuna can and hold it up.",
     "Lift the tuna fish can off the table."},
    {"Pick up the gelatin box and lift it.", "Grasp the gelatin box and hold it up.",
     "Lift the gelatin box off the table."},
    {"Pick up the pudding box and lift it.", "Grasp the pudding box and hold it up.",
     "Lift the pudding box off the table."},
}};

void Layout(engine::WorldModel& model) {
  for (const std::string& name : engine::TavisHeadObjectNames())
    model.objects.push_back(engine::MakeCatalogObject(name));
  model.static_parts.push_back(engine::MakeTable());
}

void Reset(const engine::WorldModel& model, Split split, engine::BatchState& state, int env) {
  engine::RandomStream& rng = state.task_rng[env];
  // sample_target draws before the placements: the target, then its phrasing.
  const int target = rng.UniformInt(model.num_task_objects());
  const int prompt = rng.UniformInt(static_cast<int>(kPrompts[0].size()));
  const std::vector<Placement> placements =
      SampleSeparatedPlacements(ClutterPlacementRanges(split), model.num_task_objects(), rng);
  for (int object = 0; object < model.num_task_objects(); ++object) {
    PlaceUpright(state, env, object, placements[object].position, placements[object].yaw);
  }
  state.task[env].target = target;
  state.task[env].prompt_variant = prompt;
}

const char* Prompt(const engine::BatchState& state, int env) { return TargetPrompt(kPrompts, state, env); }

std::unique_ptr<Expert> MakeExpert(const engine::WorldModel& model, int num_envs, expert::ExpertMode mode) {
  expert::PickExpertSettings settings;
  settings.mode = mode;
  return std::make_unique<expert::PickExpert>(model, num_envs, settings);
}

}  // namespace

ScenarioDef ClutterPickLift() {
  ScenarioDef def{"clutter-pick-lift",
                  "ClutterPickLiftTask",
                  Suite::kTavisHead,
                  LiftAbove(kHeadLiftSuccessZ),
                  &Layout,
                  &Reset,
                  /*update=*/nullptr,
                  &Prompt,
                  &MakeExpert,
                  /*cue_objects=*/{},
                  /*black_cameras=*/{},
                  /*stages=*/{},
                  /*target_facts=*/nullptr};
  def.stages = PickStages(def.success);
  def.gaze_anchors = PickGazeAnchors(def.stages);
  def.distractor_zones = &ClutterDistractorZones;
  def.target_zones = &ClutterTargetZones;
  // The prompt reworded under the language perturbation levels (configs/perturbations/language.yaml).
  def.paraphrases = {
      {"paraphrase", {"Take hold of the {object} and raise it above the table."}},
      {"paraphrase-terse", {"{object}: lift."}},
      {"paraphrase-synonyms",
       {"Could you pick the {object} up off the table?", "I need the {object}; lift it for me.",
        "Raise the {object} into the air."}},
  };
  return def;
}

}  // namespace tavis::scenarios

#include "scenarios/occluded_reach.h"

#include "engine/object_catalog.h"
#include "scenarios/expert/pick_expert.h"
#include "scenarios/object_placement.h"
#include "scenarios/tabletop.h"

namespace tavis::scenarios {
namespace {

engine::StaticPart ScreenPart(const std::string& name, const Vec3& size, const Vec3& centre,
                              const std::string& appearance) {
  engine::StaticPart part;
  part.name = name;
  part.shape = {ShapeKind::kBox, size};
  part.X_WS = MakeTransform(centre, Mat3::Identity());
  part.material = engine::Material::kDefault;
  part.appearance = appearance;
  return part;
}

void Layout(engine::WorldModel& model) {
  for (const std::string& name : engine::TavisHeadObjectNames())
    model.objects.push_back(engine::MakeCatalogObject(name));
  model.static_parts.push_back(engine::MakeTable());
  model.static_parts.push_back(ScreenPart("screen_base", {0.15, 0.10, 0.02}, {0.27, 0.0, 1.01}, "screen_frame"));
  model.static_parts.push_back(ScreenPart("screen_post", {0.03, 0.03, 0.10}, {0.27, 0.0, 1.07}, "screen_frame"));
  model.static_parts.push_back(ScreenPart("screen_panel", {0.015, 0.16, 0.40}, {0.27, 0.0, 1.32}, "screen_panel"));
}

// Where the target stands behind the screen: x and y ranges of the split.
PlacementRanges TargetRanges(Split split) {
  return split == Split::kOodSpatial ? XyRanges({0.36, 0.53}, {-0.30, 0.30}) : XyRanges({0.40, 0.50}, {-0.20, 0.20});
}

void Reset(const engine::WorldModel& model, Split split, engine::BatchState& state, int env) {
  engine::RandomStream& rng = state.task_rng[env];
  const PlacementRanges ranges = TargetRanges(split);
  const Range x = ranges.x;
  const Range y = ranges.y;
  // Draw order: target, x, y, yaw.
  const int target = rng.UniformInt(model.num_task_objects());
  const double px = rng.Uniform(x.low, x.high);
  const double py = rng.Uniform(y.low, y.high);
  const double yaw = rng.Uniform(-M_PI, M_PI);
  for (int object = 0; object < model.num_task_objects(); ++object) state.object_enabled_at(env, object) = 0;
  PlaceUpright(state, env, target, Vec3(px, py, kObjectDropZ), yaw);
  state.task[env].target = target;
}

// Distractors stand behind the target's area as the robot sees it, where no reach around the
// screen passes; a moved target stays in the widest split's area behind the screen.
std::vector<SupportZone> DistractorZones(const engine::BatchState&, int) {
  return {AlignedZone(0.62, 0.85, -0.30, 0.30, engine::kTableHeight)};
}

std::vector<SupportZone> TargetZones(const engine::BatchState&, int) {
  const PlacementRanges wide = TargetRanges(Split::kOodSpatial);
  return {AlignedZone(wide.x.low, wide.x.high, wide.y.low, wide.y.high, engine::kTableHeight)};
}

const char* Prompt(const engine::BatchState&, int) {
  return "Reach around the screen and pick up the object behind it.";
}

std::unique_ptr<Expert> MakeExpert(const engine::WorldModel& model, int num_envs, expert::ExpertMode mode) {
  expert::PickExpertSettings settings;
  settings.mode = mode;
  settings.lift_to_z = kHandsLiftSuccessZ + kExpertLiftPastSuccess;
  settings.grasp_height = 0.012;
  // Coming down from above where the arm clears the screen, else reaching in along the hand from
  // beside the screen and withdrawing the same way before lifting.
  settings.grasp_candidates = expert::TableAndSideGraspCandidates();
  return std::make_unique<expert::PickExpert>(model, num_envs, settings);
}

}  // namespace

ScenarioDef OccludedReach() {
  ScenarioDef def{"occluded-reach",
                  "OccludedReachTask",
                  Suite::kTavisHands,
                  LiftAbove(kHandsLiftSuccessZ),
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
  def.distractor_zones = &DistractorZones;
  def.target_zones = &TargetZones;
  // The prompt reworded under the language perturbation levels (configs/perturbations/language.yaml).
  def.paraphrases = {
      {"paraphrase", {"The object is hidden behind the screen; reach around it and pick it up."}},
      {"paraphrase-terse", {"Behind screen: pick up."}},
      {"paraphrase-synonyms",
       {"An item stands behind the monitor; get it.", "Reach behind the display and lift the item there.",
        "Pick up the thing that the screen hides from view."}},
  };
  return def;
}

}  // namespace tavis::scenarios

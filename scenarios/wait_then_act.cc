#include "scenarios/wait_then_act.h"

#include "engine/object_catalog.h"
#include "scenarios/expert/pick_expert.h"
#include "scenarios/object_placement.h"
#include "scenarios/tabletop.h"
#include "scenarios/task_state.h"

namespace tavis::scenarios {
namespace {

constexpr const char* kLightName = "signal_light";
constexpr double kLightZ = 1.03;

void SetLightColour(engine::BatchState& state, int env, int light, bool green) {
  float* rgb = state.object_rgb_row(env, light);
  rgb[0] = green ? 0.0f : 1.0f;
  rgb[1] = green ? 1.0f : 0.0f;
  rgb[2] = 0.0f;
}

void Layout(engine::WorldModel& model) {
  for (const std::string& name : engine::TavisHeadObjectNames())
    model.objects.push_back(engine::MakeCatalogObject(name));
  engine::ObjectSpec light;
  light.name = kLightName;
  light.shape = {ShapeKind::kSphere, Vec3::Constant(0.03)};
  light.motion = engine::ObjectMotion::kKinematic;
  light.collides = false;  // visual only, as in the reference
  light.appearance = "signal_light";
  model.objects.push_back(light);
  model.static_parts.push_back(engine::MakeTable());
}

// Where the object stands: x and y ranges of the split.
PlacementRanges ObjectRanges(Split split) {
  return split == Split::kOodSpatial ? XyRanges({0.30, 0.50}, {-0.20, 0.20}) : XyRanges({0.35, 0.45}, {-0.12, 0.12});
}

void Reset(const engine::WorldModel& model, Split split, engine::BatchState& state, int env) {
  engine::RandomStream& rng = state.task_rng[env];
  const bool wide = split == Split::kOodSpatial;
  const PlacementRanges object_ranges = ObjectRanges(split);
  const Range object_x = object_ranges.x;
  const Range object_y = object_ranges.y;
  const Range light_x = wide ? Range{0.55, 0.75} : Range{0.60, 0.70};
  const Range light_y = wide ? Range{-0.15, 0.15} : Range{-0.10, 0.10};
  const Range delay_s = wide ? Range{2.0, 8.0} : Range{2.0, 5.0};
  const int num_ycb = static_cast<int>(engine::TavisHeadObjectNames().size());
  // Reference draw order: target, delay, object x, y, yaw, light x, y.
  const int target = rng.UniformInt(num_ycb);
  const double delay = rng.Uniform(delay_s.low, delay_s.high);
  const double px = rng.Uniform(object_x.low, object_x.high);
  const double py = rng.Uniform(object_y.low, object_y.high);
  const double yaw = rng.Uniform(-M_PI, M_PI);
  const double lx = rng.Uniform(light_x.low, light_x.high);
  const double ly = rng.Uniform(light_y.low, light_y.high);
  for (int object = 0; object < num_ycb; ++object) state.object_enabled_at(env, object) = 0;
  PlaceUpright(state, env, target, Vec3(px, py, kObjectDropZ), yaw);
  WaitThenActVars& vars = ResetTaskState<WaitThenActVars>(state, env);
  vars.light = model.ObjectIndex(kLightName);
  PlaceUpright(state, env, vars.light, Vec3(lx, ly, kLightZ), 0.0);
  SetLightColour(state, env, vars.light, false);
  state.task[env].target = target;
  // green_step = int(delay_s / step_dt) at the 20 Hz policy rate.
  vars.go_policy_step = static_cast<int>(std::floor(delay * model.physics.policy_hz));
}

// The reference flips the light inside its success term once the episode's policy-step count
// reaches green_step; control ticks count three to a policy step.
void Update(const engine::WorldModel& model, engine::BatchState& state, int env) {
  WaitThenActVars& vars = TaskState<WaitThenActVars>(state, env);
  if (vars.go) return;
  if (state.control_step[env] >= vars.go_policy_step * model.physics.controls_per_policy()) {
    vars.go = true;
    SetLightColour(state, env, vars.light, true);
  }
}

bool LightIsGreen(const engine::BatchState& state, int env) { return TaskState<WaitThenActVars>(state, env).go; }

// Distractors stand to either side of the light and behind it, out of the head's line of sight
// to the light and beyond the object's reach; a moved target stays in the widest split's area.
std::vector<SupportZone> DistractorZones(const engine::BatchState&, int) {
  return {AlignedZone(0.50, 0.76, 0.22, 0.40, engine::kTableHeight),
          AlignedZone(0.50, 0.76, -0.40, -0.22, engine::kTableHeight),
          AlignedZone(0.82, 0.97, -0.30, 0.30, engine::kTableHeight)};
}

std::vector<SupportZone> TargetZones(const engine::BatchState&, int) {
  const PlacementRanges wide = ObjectRanges(Split::kOodSpatial);
  return {AlignedZone(wide.x.low, wide.x.high, wide.y.low, wide.y.high, engine::kTableHeight)};
}

const char* Prompt(const engine::BatchState&, int) {
  return "Watch the red light. When it turns green, pick up the object.";
}

std::unique_ptr<Expert> MakeExpert(const engine::WorldModel& model, int num_envs, expert::ExpertMode mode) {
  expert::PickExpertSettings settings;
  settings.mode = mode;
  settings.cue_object = model.ObjectIndex(kLightName);
  settings.go_signal = &LightIsGreen;
  return std::make_unique<expert::PickExpert>(model, num_envs, settings);
}

}  // namespace

ScenarioDef WaitThenAct() {
  SuccessRule success = LiftAbove(kHeadLiftSuccessZ);
  success.after_go = &LightIsGreen;  // lifted before the light turns green does not count
  ScenarioDef def{"wait-then-act",
                  "WaitThenActTask",
                  Suite::kTavisHead,
                  success,
                  &Layout,
                  &Reset,
                  &Update,
                  &Prompt,
                  &MakeExpert,
                  /*cue_objects=*/{kLightName},
                  /*black_cameras=*/{},
                  /*stages=*/{},
                  /*target_facts=*/nullptr};
  def.stages = PickStages(def.success, kLightName);
  def.gaze_anchors = PickGazeAnchors(def.stages, "light");
  def.distractor_zones = &DistractorZones;
  def.target_zones = &TargetZones;
  // The prompt reworded under the language perturbation levels (configs/perturbations/language.yaml).
  def.paraphrases = {
      {"paraphrase", {"Keep an eye on the red lamp and only pick up the object once it has turned green."}},
      {"paraphrase-terse", {"Green light, then lift."}},
      {"paraphrase-synonyms",
       {"Don't move until the lamp goes from red to green, then lift the item.",
        "Wait for the signal to show green; then pick the item up.",
        "When the red light changes to green, grab the item and raise it."}},
  };
  return def;
}

}  // namespace tavis::scenarios

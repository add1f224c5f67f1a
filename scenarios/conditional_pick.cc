#include "scenarios/conditional_pick.h"

#include "engine/object_catalog.h"
#include "scenarios/expert/pick_expert.h"
#include "scenarios/object_placement.h"
#include "scenarios/tabletop.h"
#include "scenarios/task_state.h"

namespace tavis::scenarios {
namespace {

constexpr const char* kCardName = "cue_card";
constexpr double kCardZ = 1.002;

void Layout(engine::WorldModel& model) {
  for (const std::string& name : engine::TavisHeadObjectNames())
    model.objects.push_back(engine::MakeCatalogObject(name));
  engine::ObjectSpec card;
  card.name = kCardName;
  card.shape = {ShapeKind::kBox, Vec3(0.08, 0.05, 0.003)};
  card.motion = engine::ObjectMotion::kKinematic;
  card.collides = false;  // visual only, as in the reference
  card.appearance = "cue_card";
  model.objects.push_back(card);
  model.static_parts.push_back(engine::MakeTable());
}

struct Zones {
  Range left_x, left_y, right_x, right_y, card_x, card_y;
};

Zones ZonesFor(Split split) {
  if (split == Split::kOodSpatial) {
    return {{0.30, 0.50}, {0.10, 0.35}, {0.30, 0.50}, {-0.35, -0.10}, {0.30, 0.50}, {-0.08, 0.08}};
  }
  return {{0.35, 0.45}, {0.15, 0.25}, {0.35, 0.45}, {-0.25, -0.15}, {0.35, 0.45}, {-0.05, 0.05}};
}

void Reset(const engine::WorldModel& model, Split split, engine::BatchState& state, int env) {
  engine::RandomStream& rng = state.task_rng[env];
  const Zones zones = ZonesFor(split);
  const int num_ycb = static_cast<int>(engine::TavisHeadObjectNames().size());
  // Reference draw order: the two objects, the card's colour, left pose, right pose, card pose.
  const std::vector<int> order = rng.Sample(num_ycb, 2);
  const int left = order[0];
  const int right = order[1];
  const bool card_is_red = rng.UniformInt(2) == 0;
  for (int object = 0; object < num_ycb; ++object) state.object_enabled_at(env, object) = 0;
  for (const auto& [object, x, y] :
       {std::tuple{left, zones.left_x, zones.left_y}, std::tuple{right, zones.right_x, zones.right_y}}) {
    const double px = rng.Uniform(x.low, x.high);
    const double py = rng.Uniform(y.low, y.high);
    const double yaw = rng.Uniform(-M_PI, M_PI);
    PlaceUpright(state, env, object, Vec3(px, py, kObjectDropZ), yaw);
  }
  const double cx = rng.Uniform(zones.card_x.low, zones.card_x.high);
  const double cy = rng.Uniform(zones.card_y.low, zones.card_y.high);
  const int card = model.ObjectIndex(kCardName);
  PlaceUpright(state, env, card, Vec3(cx, cy, kCardZ), 0.0);
  float* rgb = state.object_rgb_row(env, card);
  rgb[0] = card_is_red ? 1.0f : 0.0f;
  rgb[1] = card_is_red ? 0.0f : 1.0f;
  rgb[2] = 0.0f;
  state.task[env].target = card_is_red ? left : right;
  ResetTaskState<ConditionalPickVars>(state, env).card_is_red = card_is_red;
}

const char* Prompt(const engine::BatchState&, int) {
  return "Look at the card. If it is red, pick the object on the left. If it is green, pick the object on the right.";
}

// The card's rule names the target by its side: red the left object, green the right.
TargetFacts Facts(const engine::BatchState& state, int env) {
  return {{"side", TaskState<ConditionalPickVars>(state, env).card_is_red ? "left" : "right"}};
}

// Distractors stand behind the objects and the card as the robot sees them: no reach passes
// there and the head's line of sight to the card stays clear. A moved target stays on its own
// side, in the widest split's zone for it, so the card's rule still names it.
std::vector<SupportZone> DistractorZones(const engine::BatchState&, int) {
  return {AlignedZone(0.56, 0.78, -0.30, 0.30, engine::kTableHeight)};
}

std::vector<SupportZone> TargetZones(const engine::BatchState& state, int env) {
  const Zones wide = ZonesFor(Split::kOodSpatial);
  const bool left = TaskState<ConditionalPickVars>(state, env).card_is_red;
  const Range& x = left ? wide.left_x : wide.right_x;
  const Range& y = left ? wide.left_y : wide.right_y;
  return {AlignedZone(x.low, x.high, y.low, y.high, engine::kTableHeight)};
}

std::unique_ptr<Expert> MakeExpert(const engine::WorldModel& model, int num_envs, expert::ExpertMode mode) {
  expert::PickExpertSettings settings;
  settings.mode = mode;
  settings.cue_object = model.ObjectIndex(kCardName);
  return std::make_unique<expert::PickExpert>(model, num_envs, settings);
}

}  // namespace

ScenarioDef ConditionalPick() {
  ScenarioDef def{"conditional-pick",
                  "ConditionalPickTask",
                  Suite::kTavisHead,
                  LiftAbove(kHeadLiftSuccessZ),
                  &Layout,
                  &Reset,
                  /*update=*/nullptr,
                  &Prompt,
                  &MakeExpert,
                  /*cue_objects=*/{kCardName},
                  /*black_cameras=*/{},
                  /*stages=*/{},
                  /*target_facts=*/nullptr};
  def.stages = PickStages(def.success, kCardName);
  def.gaze_anchors = PickGazeAnchors(def.stages, "card");
  def.target_facts = &Facts;
  def.distractor_zones = &DistractorZones;
  def.target_zones = &TargetZones;
  // The prompt reworded under the language perturbation levels (configs/perturbations/language.yaml).
  def.paraphrases = {
      {"paraphrase", {"Check the colour of the card: red means take the left object, green means take the right one."}},
      {"paraphrase-terse", {"Card red: left object. Card green: right object. Lift it."}},
      {"paraphrase-synonyms",
       {"The card tells you which side: red for the item on your left, green for the one on your right. Lift that "
        "item.",
        "Read the card first. A red card means the left item, a green card the right item; pick it up.",
        "Which item to lift depends on the card's colour: left if red, right if green."}},
  };
  return def;
}

}  // namespace tavis::scenarios

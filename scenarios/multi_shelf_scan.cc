#include "scenarios/multi_shelf_scan.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "engine/object_catalog.h"
#include "kinematics/shape.h"
#include "scenarios/expert/pick_expert.h"
#include "scenarios/object_placement.h"
#include "scenarios/tabletop.h"

namespace tavis::scenarios {
namespace {

constexpr double kSuccessMaxX = 0.52 - 0.055 - 0.03;  // 0.435, the code's threshold

// Cabinet constants (reference 4.5).
constexpr double kCentreX = 0.52;
constexpr double kDepth = 0.11;
constexpr double kWidth = 0.70;
constexpr double kBoard = 0.02;
constexpr double kBackThickness = 0.01;
constexpr std::array<double, 3> kShelfZ = {0.97, 1.10, 1.27};
constexpr double kTopZ = 1.52;
constexpr double kUnitMidZ = 1.245;
constexpr double kUnitSpan = 0.57;
constexpr std::array<double, 2> kSlotY = {0.15, -0.15};

constexpr TargetPrompts kPrompts = {{
    {"Find the tomato soup can on the shelf and bring it to me.", "Retrieve the soup can from the shelves.",
     "Look through the shelves, find the red soup can, and take it."},
    {"Find the potted meat can on the shelf and bring it to me.", "Retrieve the spam can from the shelves.",
     "Look through the shelves, find the meat can, and take it."},
    {"Find the tuna fish can on the shelf and bring it to me.", "Retrieve the tuna can from the shelves.",
     "Look through the shelves, find the tuna can, and take it."},
    {"Find the gelatin box on the shelf and bring it to me.", "Retrieve the gelatin box from the shelves.",
     "Look through the shelves, find the gelatin box, and take it."},
    {"Find the pudding box on the shelf and bring it to me.", "Retrieve the pudding box from the shelves.",
     "Look through the shelves, find the pudding box, and take it."},
}};

engine::StaticPart Panel(const std::string& name, const Vec3& size, const Vec3& centre) {
  engine::StaticPart part;
  part.name = name;
  part.shape = {ShapeKind::kBox, size};
  part.X_WS = MakeTransform(centre, Mat3::Identity());
  part.material = engine::Material::kTable;
  part.appearance = "wood";
  return part;
}

void Layout(engine::WorldModel& model) {
  for (const std::string& name : engine::TavisHeadObjectNames())
    model.objects.push_back(engine::MakeCatalogObject(name));
  const Vec3 board(kDepth, kWidth, kBoard);
  for (std::size_t shelf = 0; shelf < kShelfZ.size(); ++shelf) {
    model.static_parts.push_back(Panel("shelf_board_" + std::to_string(shelf), board, {kCentreX, 0.0, kShelfZ[shelf]}));
  }
  model.static_parts.push_back(Panel("shelf_board_top", board, {kCentreX, 0.0, kTopZ}));
  const Vec3 side(kDepth, kBoard, kUnitSpan);
  const double side_y = 0.5 * kWidth + 0.5 * kBoard;
  model.static_parts.push_back(Panel("shelf_side_left", side, {kCentreX, side_y, kUnitMidZ}));
  model.static_parts.push_back(Panel("shelf_side_right", side, {kCentreX, -side_y, kUnitMidZ}));
  model.static_parts.push_back(Panel("shelf_back", {kBackThickness, kWidth, kUnitSpan},
                                     {kCentreX + 0.5 * kDepth + 0.5 * kBackThickness, 0.0, kUnitMidZ}));
  // The task's own shadow light: intensity 1000 from above-behind the robot into the cabinet.
  model.lighting.distant_direction = Vec3(0.643, -0.236, -0.728);
  model.lighting.distant_intensity = 1000.0;
}

void Reset(const engine::WorldModel& model, Split split, engine::BatchState& state, int env) {
  engine::RandomStream& rng = state.task_rng[env];
  const double jitter_x = 0.03;
  const double jitter_y = split == Split::kOodSpatial ? 0.10 : 0.03;
  constexpr int kSlots = static_cast<int>(kShelfZ.size() * kSlotY.size());
  // Reference draw order: the five slots, the target, its phrasing, then each object's pose.
  const std::vector<int> slots = rng.Sample(kSlots, model.num_task_objects());
  const int target = rng.UniformInt(model.num_task_objects());
  const int prompt = rng.UniformInt(static_cast<int>(kPrompts[0].size()));
  for (int object = 0; object < model.num_task_objects(); ++object) {
    const int slot = slots[static_cast<std::size_t>(object)];
    const double shelf_z = kShelfZ[static_cast<std::size_t>(slot) / kSlotY.size()];
    const double slot_y = kSlotY[static_cast<std::size_t>(slot) % kSlotY.size()];
    double x = std::clamp(kCentreX + rng.Uniform(-jitter_x, jitter_x), 0.485, 0.555);
    const double y = std::clamp(slot_y + rng.Uniform(-jitter_y, jitter_y), -0.32, 0.32);
    const double yaw = rng.Uniform(-M_PI, M_PI);
    // A turned object at the back can overlap the back panel. PhysX pushes it out; ODE's exact
    // solver fails on the wedged contacts and drops it through the board (docs/fidelity.md), so
    // it starts just touching the panel instead.
    const Vec3 half = BoundingHalfSize(model.objects[static_cast<std::size_t>(object)].shape);
    const double half_depth = half.x() * std::abs(std::cos(yaw)) + half.y() * std::abs(std::sin(yaw));
    x = std::min(x, kCentreX + 0.5 * kDepth - half_depth - 0.002);
    PlaceUpright(state, env, object, Vec3(x, y, shelf_z + 0.01 + 0.04), yaw);
  }
  state.task[env].target = target;
  state.task[env].prompt_variant = prompt;
}

const char* Prompt(const engine::BatchState& state, int env) { return TargetPrompt(kPrompts, state, env); }

// The shelf an object at height z stands on: the highest board below it, -1 below them all.
int ShelfUnder(double z) {
  int under = -1;
  for (std::size_t shelf = 0; shelf < kShelfZ.size(); ++shelf) {
    if (kShelfZ[shelf] < z) under = static_cast<int>(shelf);
  }
  return under;
}

// The height of a shelf board's top face (the lowest board's for -1).
double ShelfSurfaceZ(int shelf) { return kShelfZ[static_cast<std::size_t>(std::max(shelf, 0))] + 0.5 * kBoard; }

// The shelf the target stands on (none below every board, where a reset never puts it).
TargetFacts Facts(const engine::BatchState& state, int env) {
  const int shelf = ShelfUnder(state.ObjectPosition(env, state.target(env)).z());
  if (shelf < 0) return {};
  return {{"shelf", shelf}};
}

// A shelf board's area between the side panels, inset by `inset` from every edge.
SupportZone BoardZone(double surface_z, double y_low, double y_high, double inset) {
  return AlignedZone(kCentreX - 0.5 * kDepth + inset, kCentreX + 0.5 * kDepth - inset, y_low, y_high, surface_z);
}

// Distractors stand in the slot no object was given (five objects, six slots), clear of the
// other slot's reach on that shelf, and on top of the cabinet: no reach into a slot passes there.
std::vector<SupportZone> DistractorZones(const engine::BatchState& state, int env) {
  std::array<bool, kShelfZ.size() * kSlotY.size()> taken{};
  for (int object = 0; object < state.num_objects; ++object) {
    if (!state.object_enabled_at(env, object) || object >= static_cast<int>(engine::TavisHeadObjectNames().size()))
      continue;
    const Vec3 p = state.ObjectPosition(env, object);
    // Slots alternate sides, +y first (kSlotY); an object's jitter never crosses the middle.
    taken[static_cast<std::size_t>(std::max(ShelfUnder(p.z()), 0)) * kSlotY.size() + (p.y() >= 0.0 ? 0 : 1)] = true;
  }
  std::vector<SupportZone> zones;
  for (std::size_t slot = 0; slot < taken.size(); ++slot) {
    if (taken[slot]) continue;
    const double y = kSlotY[slot % kSlotY.size()];
    zones.push_back(BoardZone(ShelfSurfaceZ(static_cast<int>(slot / kSlotY.size())), y - 0.10, y + 0.10, 0.005));
  }
  zones.push_back(BoardZone(kTopZ + 0.5 * kBoard, -0.30, 0.30, 0.005));
  return zones;
}

// A moved target stays on its shelf board, its centre clear of the board's front and back edges
// and of the side panels, where the straight reach into the cabinet still comes.
std::vector<SupportZone> TargetZones(const engine::BatchState& state, int env) {
  return {BoardZone(ShelfSurfaceZ(ShelfUnder(state.ObjectPosition(env, state.target(env)).z())), -0.28, 0.28, 0.02)};
}

// Scans the three rows bottom to top, then reaches level into the target's slot from the front
// and pulls it straight out past the success line.
std::unique_ptr<Expert> MakeExpert(const engine::WorldModel& model, int num_envs, expert::ExpertMode mode) {
  expert::PickExpertSettings settings;
  settings.mode = mode;
  for (const double shelf_z : kShelfZ) settings.scan_points.push_back(Vec3(kCentreX, 0.0, shelf_z + 0.05));
  settings.approach_distance = 0.15;
  settings.lift_to_z = std::nullopt;  // withdrawing 15 cm takes the object past the success line
  settings.grasp_candidates = expert::ShelfGraspCandidates();
  settings.support_under_hand = false;
  settings.reach_heading = [](const engine::BatchState&, int) { return 0.0; };  // straight in
  return std::make_unique<expert::PickExpert>(model, num_envs, settings);
}

}  // namespace

ScenarioDef MultiShelfScan() {
  ScenarioDef def{"multi-shelf-scan",
                  "MultiShelfScanTask",
                  Suite::kTavisHead,
                  PullOutPast(kSuccessMaxX),
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
  def.target_facts = &Facts;
  def.distractor_zones = &DistractorZones;
  def.target_zones = &TargetZones;
  // The prompt reworded under the language perturbation levels (configs/perturbations/language.yaml).
  def.paraphrases = {
      {"paraphrase", {"Search the shelves for the {object} and pull it out toward me."}},
      {"paraphrase-terse", {"Shelves: fetch {object}."}},
      {"paraphrase-synonyms",
       {"Somewhere on these shelves is the {object}; please fetch it.",
        "Could you find the {object} in the cabinet and take it out?",
        "Check each shelf for the {object} and pull it out to me."}},
  };
  return def;
}

}  // namespace tavis::scenarios

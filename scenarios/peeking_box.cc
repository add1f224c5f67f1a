#include "scenarios/peeking_box.h"

#include <array>
#include <cmath>

#include "engine/object_catalog.h"
#include "scenarios/expert/pick_expert.h"
#include "scenarios/object_placement.h"
#include "scenarios/tabletop.h"
#include "scenarios/task_state.h"

namespace tavis::scenarios {
namespace {

constexpr double kObjectZ = 1.05;

// Box walls in box-local coordinates (reference 4.6): the lid and the front and back panels span
// the full width so that a head-on view cannot tell which side is open.
struct Wall {
  const char* name;
  Vec3 size;
  Vec3 centre;  // box-local x, y; world z
};
constexpr double kT = 0.008;
constexpr const char* kWallBackName = "box_wall_back";
constexpr const char* kWallFrontName = "box_wall_front";
constexpr const char* kWallPosYName = "box_wall_pos_y";
constexpr const char* kWallNegYName = "box_wall_neg_y";
const std::array<Wall, 5> kWalls = {{
    {kWallBackName, {kT, 0.156, 0.20}, {0.204, 0.0, 1.095}},
    {kWallFrontName, {kT, 0.156, 0.20}, {-0.204, 0.0, 1.095}},
    {"box_wall_top", {0.416, 0.156, kT}, {0.0, 0.0, 1.199}},
    {kWallPosYName, {0.40, kT, 0.20}, {0.0, 0.074, 1.095}},
    {kWallNegYName, {0.40, kT, 0.20}, {0.0, -0.074, 1.095}},
}};
constexpr double kHalfWidth = 0.074;  // box-local y of the side walls' centres

void Layout(engine::WorldModel& model) {
  for (const std::string& name : engine::TavisHeadObjectNames())
    model.objects.push_back(engine::MakeCatalogObject(name));
  for (const Wall& wall : kWalls) {
    engine::ObjectSpec spec;
    spec.name = wall.name;
    spec.shape = {ShapeKind::kBox, wall.size};
    spec.motion = engine::ObjectMotion::kKinematic;
    spec.material = engine::Material::kTable;
    spec.appearance = "wood";
    model.objects.push_back(spec);
  }
  model.static_parts.push_back(engine::MakeTable());
}

void Reset(const engine::WorldModel& model, Split split, engine::BatchState& state, int env) {
  engine::RandomStream& rng = state.task_rng[env];
  const bool wide = split == Split::kOodSpatial;
  const Range box_x = wide ? Range{0.39, 0.47} : Range{0.41, 0.45};
  const Range box_y = {-0.04, 0.04};
  const double max_yaw = (wide ? 10.0 : 5.0) * M_PI / 180.0;
  const Range object_dx = {-0.04, 0.04};
  const Range object_dy = wide ? Range{-0.04, 0.04} : Range{-0.02, 0.02};
  // Reference draw order: box centre and yaw, open side, target, object offset, object yaw.
  const double cx = rng.Uniform(box_x.low, box_x.high);
  const double cy = rng.Uniform(box_y.low, box_y.high);
  const double yaw = rng.Uniform(-max_yaw, max_yaw);
  const bool open_pos_y = rng.UniformInt(2) == 0;
  const int num_ycb = static_cast<int>(engine::TavisHeadObjectNames().size());
  const int target = rng.UniformInt(num_ycb);
  const Mat3 R = Eigen::AngleAxisd(yaw, Vec3::UnitZ()).toRotationMatrix();
  const Vec3 centre(cx, cy, 0.0);
  for (const Wall& wall : kWalls) {
    const Vec3 offset(wall.centre.x(), wall.centre.y(), 0.0);
    const Vec3 p = centre + R * offset + Vec3(0.0, 0.0, wall.centre.z());
    PlaceUpright(state, env, model.ObjectIndex(wall.name), p, yaw);
  }
  state.object_enabled_at(env, model.ObjectIndex(open_pos_y ? kWallPosYName : kWallNegYName)) = 0;
  const double dx = rng.Uniform(object_dx.low, object_dx.high);
  const double dy = rng.Uniform(object_dy.low, object_dy.high);
  const double object_yaw = rng.Uniform(-M_PI, M_PI);
  for (int object = 0; object < num_ycb; ++object) state.object_enabled_at(env, object) = 0;
  PlaceUpright(state, env, target, centre + R * Vec3(dx, dy, 0.0) + Vec3(0.0, 0.0, kObjectZ), object_yaw);
  state.task[env].target = target;
  PeekingBoxVars& vars = ResetTaskState<PeekingBoxVars>(state, env);
  vars.open_side = open_pos_y ? 1 : -1;
  vars.wall_back = model.ObjectIndex(kWallBackName);
  vars.wall_front = model.ObjectIndex(kWallFrontName);
}

const char* Prompt(const engine::BatchState&, int) { return "Retrieve the object from inside the box."; }

TargetFacts Facts(const engine::BatchState& state, int env) {
  return {{"open_side", TaskState<PeekingBoxVars>(state, env).open_side > 0 ? "left" : "right"}};
}

double BoxYaw(const engine::BatchState& state, int env) {
  const Mat3 R = state.ObjectOrientation(env, TaskState<PeekingBoxVars>(state, env).wall_back).toRotationMatrix();
  return std::atan2(R(1, 0), R(0, 0));
}

// +1 when the robot's left (+y) side is open, -1 for the right.
double OpenSide(const engine::BatchState& state, int env) { return TaskState<PeekingBoxVars>(state, env).open_side; }

// The middle of the box, between its back and front walls.
Vec3 BoxCentre(const engine::BatchState& state, int env) {
  const PeekingBoxVars& vars = TaskState<PeekingBoxVars>(state, env);
  return 0.5 * (state.ObjectPosition(env, vars.wall_back) + state.ObjectPosition(env, vars.wall_front));
}

// Heading of a level hand entering the box through the side `side` (+1: +y): across the box,
// turned 0.7 rad toward the front as the arm on that side naturally reaches in.
double IntoBoxHeading(const engine::BatchState& state, int env, double side) {
  constexpr double kForwardTurn = 0.7;
  return BoxYaw(state, env) - side * (M_PI / 2 - kForwardTurn);
}

// Distractors stand on the table behind the box as the robot sees it: the wrists peek and the
// hand reaches in from the sides, so nothing the task needs passes there.
std::vector<SupportZone> DistractorZones(const engine::BatchState&, int) {
  return {AlignedZone(0.74, 0.95, -0.30, 0.30, engine::kTableHeight)};
}

// A moved target stays inside the box, its centre within 8 cm of the box's middle along it and
// 3 cm across it (the widest split places it within 4 cm either way; a target moved further
// across, away from the open side the hand reaches through, is beyond the expert's reach).
std::vector<SupportZone> TargetZones(const engine::BatchState& state, int env) {
  const Vec3 centre = BoxCentre(state, env);
  return {{Vec3(centre.x(), centre.y(), engine::kTableHeight), BoxYaw(state, env), 0.08, 0.03}};
}

// Each wrist looks into its side of the box from 16 cm outside it, the hand a little above the
// object and pointing across the box, so the wrist camera sees the wall or the object.
std::array<RigidTransform, 2> PeekPoses(const engine::WorldModel& model, const engine::BatchState& state, int env) {
  constexpr double kPeekDistance = 0.16;
  constexpr double kPeekTilt = M_PI / 2 - 0.3;  // looking a little down into the opening
  const Vec3 centre = BoxCentre(state, env);
  const Mat3 R_box = Eigen::AngleAxisd(BoxYaw(state, env), Vec3::UnitZ()).toRotationMatrix();
  std::array<RigidTransform, 2> poses;
  for (const kinematics::Side arm : kinematics::kSides) {
    const double side = arm == kinematics::Side::kLeft ? 1.0 : -1.0;
    const Mat3 R = (Eigen::AngleAxisd(IntoBoxHeading(state, env, side), Vec3::UnitZ()) *
                    Eigen::AngleAxisd(-kPeekTilt, Vec3::UnitY()))
                       .toRotationMatrix();
    const Vec3 pads(centre.x(), centre.y(), kObjectZ + 0.06);
    const Vec3 p_pads = pads + R_box * Vec3(0.0, side * (kHalfWidth + kPeekDistance), 0.0);
    poses[kinematics::Index(arm)] = MakeTransform(p_pads - R * model.robot.gripper.pad_center, R);
  }
  return poses;
}

// Looks at the box, peeks into both sides with the wrist cameras, then reaches in level through
// the open side with the arm on that side, closes, withdraws the way it came and lifts.
std::unique_ptr<Expert> MakeExpert(const engine::WorldModel& model, int num_envs, expert::ExpertMode mode) {
  expert::PickExpertSettings settings;
  settings.mode = mode;
  settings.peek_poses = &PeekPoses;
  settings.reach_side = [](const engine::BatchState& state, int env) {
    return OpenSide(state, env) > 0.0 ? kinematics::Side::kLeft : kinematics::Side::kRight;
  };
  settings.reach_heading = [](const engine::BatchState& state, int env) {
    return IntoBoxHeading(state, env, OpenSide(state, env));
  };
  settings.grasp_candidates.clear();
  const double level = M_PI / 2;
  // Steeper hands last: a level hand's pads pass over a low object such as the tuna can.
  for (const double tilt : {level, level - 0.15, level - 0.3, level - 0.5, level - 0.7}) {
    for (const double heading : {0.0, 0.25, -0.25, 0.5, -0.5}) {
      for (const double turn : {0.0, M_PI}) {
        settings.grasp_candidates.push_back({tilt, heading, turn, /*along_hand=*/true});
      }
    }
  }
  settings.lift_to_z = kHandsLiftSuccessZ + kExpertLiftPastSuccess;
  return std::make_unique<expert::PickExpert>(model, num_envs, settings);
}

}  // namespace

ScenarioDef PeekingBox() {
  ScenarioDef def{
      "peeking-box",           "PeekingBoxTask", Suite::kTavisHands, LiftAbove(kHandsLiftSuccessZ), &Layout, &Reset,
      /*update=*/nullptr,      &Prompt,          &MakeExpert,
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
      {"paraphrase", {"There is an object hidden in the box; take it out."}},
      {"paraphrase-terse", {"Box: take object out."}},
      {"paraphrase-synonyms",
       {"Something is inside the box. Get it out and lift it.", "Take whatever is in the box out of it.",
        "Look into the box, find the item and lift it out."}},
  };
  return def;
}

}  // namespace tavis::scenarios

#include "scenarios/clutter_pick_cube.h"

#include <algorithm>
#include <array>
#include <vector>

#include "engine/object_catalog.h"
#include "scenarios/expert/arm_planner.h"
#include "scenarios/expert/pick_expert.h"
#include "scenarios/object_placement.h"
#include "scenarios/tabletop.h"

namespace tavis::scenarios {
namespace {

constexpr const char* kRedCubeName = "red_cube";

void Layout(engine::WorldModel& model) {
  for (const std::string& name : engine::TavisHeadObjectNames())
    model.objects.push_back(engine::MakeCatalogObject(name));
  model.objects.push_back(engine::MakeCatalogObject(kRedCubeName));
  model.static_parts.push_back(engine::MakeTable());
}

}  // namespace

PlacementRanges ClutterPlacementRanges(Split split) {
  PlacementRanges ranges;
  const bool wide = split == Split::kOodSpatial;
  ranges.x = wide ? Range{0.30, 0.50} : Range{0.35, 0.45};
  ranges.y = wide ? Range{-0.35, 0.35} : Range{-0.25, 0.25};
  ranges.z = {kObjectDropZ, kObjectDropZ};
  ranges.roll = {-1.5708, -1.5708};
  ranges.pitch = {0.0, 0.0};
  ranges.yaw = {-3.14159, 3.14159};
  ranges.min_separation = wide ? 0.05 : 0.10;
  return ranges;
}

std::vector<SupportZone> ClutterDistractorZones(const engine::BatchState&, int) {
  return {AlignedZone(0.56, 0.78, -0.30, 0.30, engine::kTableHeight)};
}

std::vector<SupportZone> ClutterTargetZones(const engine::BatchState&, int) {
  const PlacementRanges wide = ClutterPlacementRanges(Split::kOodSpatial);
  return {AlignedZone(wide.x.low, wide.x.high, wide.y.low, wide.y.high, engine::kTableHeight)};
}

namespace {

void Reset(const engine::WorldModel& model, Split split, engine::BatchState& state, int env) {
  engine::RandomStream& rng = state.task_rng[env];
  const std::vector<Placement> placements =
      SampleSeparatedPlacements(ClutterPlacementRanges(split), model.num_task_objects(), rng);
  // sample_trial: random.sample(TAVIS_HEAD_OBJECT_NAMES, 4); the one left out is hidden. The
  // hidden object's sampled pose still constrained the others, as in the reference.
  const int hidden = rng.Sample(static_cast<int>(engine::TavisHeadObjectNames().size()), 4)[4];
  for (int object = 0; object < model.num_task_objects(); ++object) {
    PlaceUpright(state, env, object, placements[object].position, placements[object].yaw);
    state.object_enabled_at(env, object) = object != hidden;
  }
  state.task[env].target = model.ObjectIndex(kRedCubeName);
}

const char* Prompt(const engine::BatchState&, int) { return "Find the red cube and pick it up."; }

std::unique_ptr<Expert> MakeExpert(const engine::WorldModel& model, int num_envs, expert::ExpertMode mode) {
  expert::PickExpertSettings settings;
  settings.mode = mode;
  return std::make_unique<expert::PickExpert>(model, num_envs, settings);
}

// Without the head image the teleoperator found the cube in the wrist picture-in-picture: the
// hand on the cube's side looks down at it from its own side, the wrist camera along the hand's
// approach, tilted as the table grasps are; the other hand keeps still. Of the lines of sight
// turned inward from straight ahead, the first the arm can reach is taken (none: both keep still).
std::array<RigidTransform, 2> WristLookPoses(const engine::WorldModel& model, const engine::BatchState& state,
                                             int env) {
  constexpr double kLookDistance = 0.22;                                 // m, from the cube to the pads' centre
  constexpr double kLookTilt = 0.8;                                      // rad, of the line of sight from straight down
  constexpr std::array<double, 4> kInwardTurns = {1.05, 0.5, 1.5, 0.0};  // rad
  const kinematics::RobotModel& robot = model.robot;
  const std::vector<double> q_now(state.q_row(env), state.q_row(env) + robot.num_joints());
  std::array<RigidTransform, 2> poses;
  for (const kinematics::Side side : kinematics::kSides) {
    RigidTransform X_W_ik = expert::HandPoseCanonical(robot, side, q_now.data());
    X_W_ik.translation() = robot.CanonicalToBase(X_W_ik.translation()) + robot.root_world;
    poses[static_cast<std::size_t>(kinematics::Index(side))] = X_W_ik;
  }
  const Vec3 cube = state.ObjectPosition(env, state.target(env));  // the red cube
  const kinematics::Side looking = cube.y() >= 0.0 ? kinematics::Side::kLeft : kinematics::Side::kRight;
  const double inward = looking == kinematics::Side::kLeft ? -1.0 : 1.0;  // the left hand looks toward -y
  for (const double turn : kInwardTurns) {
    const Mat3 R = (Eigen::AngleAxisd(inward * turn, Vec3::UnitZ()) * Eigen::AngleAxisd(-kLookTilt, Vec3::UnitY()))
                       .toRotationMatrix();
    const Vec3 pads = cube + kLookDistance * R.col(2);  // back along the approach (the hand's -Z)
    const RigidTransform X_W_ik = MakeTransform(pads - R * robot.gripper.pad_center, R);
    if (expert::SolveArmConfiguration(robot, looking, q_now, {X_W_ik.translation() - robot.root_world, Quat(R)})) {
      poses[static_cast<std::size_t>(kinematics::Index(looking))] = X_W_ik;
      break;
    }
  }
  return poses;
}

std::unique_ptr<Expert> MakeBlockedExpert(const engine::WorldModel& model, int num_envs, expert::ExpertMode mode) {
  expert::PickExpertSettings settings;
  settings.mode = mode;
  settings.peek_poses = &WristLookPoses;
  return std::make_unique<expert::PickExpert>(model, num_envs, settings);
}

}  // namespace

ScenarioDef ClutterPickCube() {
  ScenarioDef def{"clutter-pick-cube",
                  "ClutterPickCubeTask",
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
  // The prompt reworded under the language perturbation levels (configs/perturbations/language.yaml);
  // blocked-clutter-pick-cube has the same.
  def.paraphrases = {
      {"paraphrase", {"Locate the red block among the objects and lift it up."}},
      {"paraphrase-terse", {"Red cube: lift."}},
      {"paraphrase-synonyms",
       {"Somewhere on the table is a red block; lift it.", "Could you find the scarlet cube and hold it up?",
        "Pick up the little red box from among the things on the table."}},
  };
  return def;
}

ScenarioDef BlockedClutterPickCube() {
  ScenarioDef def = ClutterPickCube();
  def.name = "blocked-clutter-pick-cube";
  def.class_name = "BlockedClutterPickCubeTask";
  def.suite = Suite::kTavisHands;
  def.black_cameras = {"head"};
  def.make_expert = &MakeBlockedExpert;
  return def;
}

}  // namespace tavis::scenarios

#include "scenarios/peeking_box.h"

#include <array>

#include "engine/object_catalog.h"
#include "scenarios/object_placement.h"

namespace tavis::scenarios {
namespace {

constexpr int kNumYcb = 5;
constexpr int kTargetVar = 0;
constexpr int kOpenSideVar = 1;  // +1: the robot's left (+y) wall is missing, -1: the right
constexpr double kSuccessHeight = 1.25;
constexpr double kSuccessMaxSpeed = 1.0;
constexpr double kObjectZ = 1.05;

// Box walls in box-local coordinates (reference 4.6): the lid and the front and back panels span
// the full width so that a head-on view cannot tell which side is open.
struct Wall {
  const char* name;
  Vec3 size;
  Vec3 centre;  // box-local x, y; world z
};
constexpr double kT = 0.008;
const std::array<Wall, 5> kWalls = {{
    {"box_wall_back", {kT, 0.156, 0.20}, {0.204, 0.0, 1.095}},
    {"box_wall_front", {kT, 0.156, 0.20}, {-0.204, 0.0, 1.095}},
    {"box_wall_top", {0.416, 0.156, kT}, {0.0, 0.0, 1.199}},
    {"box_wall_pos_y", {0.40, kT, 0.20}, {0.0, 0.074, 1.095}},
    {"box_wall_neg_y", {0.40, kT, 0.20}, {0.0, -0.074, 1.095}},
}};
constexpr int kWallPosY = kNumYcb + 3;
constexpr int kWallNegY = kNumYcb + 4;

void Layout(engine::WorldModel& model) {
  for (const std::string& name : engine::TavisHeadObjectNames()) model.objects.push_back(engine::MakeCatalogObject(name));
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

void Reset(const engine::WorldModel&, Split split, engine::BatchState& state, int env) {
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
  const int target = rng.UniformInt(kNumYcb);
  const Mat3 R = Eigen::AngleAxisd(yaw, Vec3::UnitZ()).toRotationMatrix();
  const Vec3 centre(cx, cy, 0.0);
  for (std::size_t w = 0; w < kWalls.size(); ++w) {
    const Vec3 offset(kWalls[w].centre.x(), kWalls[w].centre.y(), 0.0);
    const Vec3 p = centre + R * offset + Vec3(0.0, 0.0, kWalls[w].centre.z());
    PlaceUpright(state, env, kNumYcb + static_cast<int>(w), p, yaw);
  }
  state.object_enabled_at(env, open_pos_y ? kWallPosY : kWallNegY) = 0;
  const double dx = rng.Uniform(object_dx.low, object_dx.high);
  const double dy = rng.Uniform(object_dy.low, object_dy.high);
  const double object_yaw = rng.Uniform(-M_PI, M_PI);
  for (int object = 0; object < kNumYcb; ++object) state.object_enabled_at(env, object) = 0;
  PlaceUpright(state, env, target, centre + R * Vec3(dx, dy, 0.0) + Vec3(0.0, 0.0, kObjectZ), object_yaw);
  state.task_vars_row(env)[kTargetVar] = target;
  state.task_vars_row(env)[kOpenSideVar] = open_pos_y ? 1.0 : -1.0;
}

bool Evaluate(const engine::WorldModel&, const engine::BatchState& state, int env) {
  const int target = static_cast<int>(state.task_vars_row(env)[kTargetVar]);
  return state.ObjectPosition(env, target).z() > kSuccessHeight &&
         state.ObjectLinearVelocity(env, target).norm() < kSuccessMaxSpeed;
}

std::string Prompt(const engine::BatchState&, int) { return "Retrieve the object from inside the box."; }

}  // namespace

ScenarioDef PeekingBox() {
  ScenarioDef def;
  def.name = "peeking-box";
  def.suite = "tavis-hands";
  def.layout = &Layout;
  def.reset = &Reset;
  def.evaluate = &Evaluate;
  def.prompt = &Prompt;
  return def;
}

}  // namespace tavis::scenarios

#include "batch/perturb/distractor_placement.h"

#include <cmath>
#include <vector>

#include "batch/perturb/scene_clearance.h"
#include "scenarios/object_placement.h"

namespace tavis::batch::perturb {
namespace {

constexpr const char* kAppearance = "distractor";
constexpr int kMaxTries = 1000;
// rad: an object stands square to its zone's edges, as things are set down on a table or a shelf,
// turned at most this much either way (a box too long for a shelf's depth then fits along it).
constexpr double kYawJitter = 15.0 * M_PI / 180.0;
constexpr double kDropHeight = 0.001;  // m: stood this far above its surface, so it starts free of it

// Looks for a place for `object` in the zones; true when found (then it stands there).
bool PlaceOne(const engine::WorldModel& model, const std::vector<scenarios::SupportZone>& zones, int object,
              engine::RandomStream& rng, engine::BatchState& state, int env) {
  const Shape& shape = model.objects[static_cast<std::size_t>(object)].shape;
  for (int attempt = 0; attempt < kMaxTries; ++attempt) {
    const scenarios::SupportZone& zone =
        zones[static_cast<std::size_t>(rng.UniformInt(static_cast<int>(zones.size())))];
    const double local_x = rng.Uniform(-zone.half_x, zone.half_x);
    const double local_y = rng.Uniform(-zone.half_y, zone.half_y);
    const double yaw = zone.yaw + 0.5 * M_PI * rng.UniformInt(4) + rng.Uniform(-kYawJitter, kYawJitter);
    const double c = std::cos(zone.yaw);
    const double s = std::sin(zone.yaw);
    const double x = zone.centre.x() + c * local_x - s * local_y;
    const double y = zone.centre.y() + s * local_x + c * local_y;
    const scenarios::expert::OrientedBox box = UprightBox(shape, x, y, zone.centre.z(), yaw);
    if (!FootprintInZone(box, zone) || !ClearOfStaticParts(model, box) ||
        !ClearOfObjectsLandingOn(model, state, env, box, zone.centre.z(), object, kDistractorClearance)) {
      continue;
    }
    scenarios::PlaceUpright(state, env, object, Vec3(x, y, zone.centre.z() + BoundingHalfSize(shape).z() + kDropHeight),
                            yaw);
    return true;
  }
  return false;
}

}  // namespace

void AddDistractorObjects(engine::WorldModel* model) {
  for (const engine::DistractorKind& kind : model->episode_perturbation.distractors.kinds) {
    engine::ObjectSpec spec;
    spec.name = "distractor_" + kind.name;
    spec.shape = kind.shape;
    spec.mass = kind.mass_kg;
    spec.material = engine::Material::kObject;
    spec.appearance = kAppearance;
    spec.distractor = true;  // the appearance axis's `distractors` texture covers these
    model->objects.push_back(spec);
  }
}

void PlaceDistractors(const engine::WorldModel& model, const scenarios::ScenarioDef& scenario,
                      engine::BatchState& state, int env) {
  const engine::EpisodePerturbation& perturbation = model.episode_perturbation;
  if (!perturbation.adds_distractors()) return;
  const int first = model.num_task_objects();
  const int kinds = perturbation.num_distractor_objects();
  for (int k = 0; k < kinds; ++k) state.object_enabled_at(env, first + k) = 0;
  engine::RandomStream rng(perturbation.seed, engine::RandomStreamId::kDistractors,
                           static_cast<uint64_t>(state.episode[static_cast<std::size_t>(env)]));
  const std::vector<int> order = rng.Sample(kinds, perturbation.distractors.count);
  const std::vector<scenarios::SupportZone> zones = scenario.distractor_zones(state, env);
  if (zones.empty()) return;
  for (int i = 0; i < perturbation.distractors.count; ++i) {
    const int kind = order[static_cast<std::size_t>(i)];
    const int object = first + kind;
    if (!PlaceOne(model, zones, object, rng, state, env)) continue;
    const Vec3& rgb = perturbation.distractors.kinds[static_cast<std::size_t>(kind)].rgb;
    float* colour = state.object_rgb_row(env, object);
    for (int c = 0; c < 3; ++c) colour[c] = static_cast<float>(rgb[c]);
  }
}

}  // namespace tavis::batch::perturb

// Where the scene perturbation axes may put an object (docs/perturbations.md): a distractor at
// an episode's reset, the target when the runtime axis moves it. An object may stand where its
// task's zone (scenarios/support_zone.h) allows and clear of everything else in the env.
#pragma once

#include "engine/batch_state.h"
#include "engine/world_model.h"
#include "scenarios/expert/grasp_clearance.h"
#include "scenarios/support_zone.h"

namespace tavis::batch::perturb {

// The collision box (as the physics collides it, scenarios::expert::ObjectBox) of `shape` standing
// upright on a surface of height surface_z at horizontal (x, y), turned `yaw`.
scenarios::expert::OrientedBox UprightBox(const Shape& shape, double x, double y, double surface_z, double yaw);

// True if the box's whole horizontal outline lies in the zone.
bool FootprintInZone(const scenarios::expert::OrientedBox& box, const scenarios::SupportZone& zone);
// True if the point's horizontal position lies in the zone.
bool PointInZone(const Vec3& point, const scenarios::SupportZone& zone);

// True if `box` stays `margin` outside every enabled dynamic object of `env` but `skip` (-1:
// none), and `fixed_margin` outside every enabled kinematic one (a box's walls, a cue).
bool ClearOfObjects(const engine::WorldModel& model, const engine::BatchState& state, int env,
                    const scenarios::expert::OrientedBox& box, int skip, double margin, double fixed_margin);
// The same for a box standing on the surface at height surface_z right after a reset, whose
// objects are still to fall onto their supports: it is compared, seen from above, with every
// object that stands on that surface or will land on it (one above it with no static part, such
// as a shelf board, in between); objects below the surface or above another support do not count.
bool ClearOfObjectsLandingOn(const engine::WorldModel& model, const engine::BatchState& state, int env,
                             const scenarios::expert::OrientedBox& box, double surface_z, int skip, double margin);
// True if `box` stays `margin` outside every collision shape of the robot (its links as
// kinematics::LinkShape boxes, both grippers' housings and pads at their measured gaps) in env's
// current configuration.
bool ClearOfRobot(const engine::WorldModel& model, const engine::BatchState& state, int env,
                  const scenarios::expert::OrientedBox& box, double margin);
// True if `box`, resting on a support, cuts into no colliding static part (the shelf board above
// it, the screen, the cabinet's panels); the support it rests on does not count.
bool ClearOfStaticParts(const engine::WorldModel& model, const scenarios::expert::OrientedBox& box);

}  // namespace tavis::batch::perturb

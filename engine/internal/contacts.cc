// PhysicsWorld's collisions: the broad phase over every geom pair in a fixed order, the contact
// joints with their friction, and the check that the world has not blown up.
#include <algorithm>
#include <cmath>

#include <ode/ode.h>

#include "engine/internal/physics_world_impl.h"

namespace tavis::engine {

using internal::GeomInfo;

namespace {

constexpr double kPadContactRadius = 0.01;  // m, effective radius of a finger pad's contact

}  // namespace

void PhysicsWorld::Impl::ComputeAabbs() {
  for (size_t i = 0; i < all_geoms.size(); ++i) {
    dGeomGetAABB(all_geoms[i], &aabbs[6 * i]);
    geom_enabled[i] = dGeomIsEnabled(all_geoms[i]) ? 1 : 0;
  }
}

void PhysicsWorld::Impl::CollideAllPairs() {
  candidate_pairs->ForEachOverlap(aabbs.data(), geom_enabled.data(),
                                  [this](int i, int j) { Collide(all_geoms[i], all_geoms[j]); });
}

void PhysicsWorld::Impl::Collide(dGeomID a, dGeomID b) {
  dBodyID body_a = dGeomGetBody(a);
  dBodyID body_b = dGeomGetBody(b);
  if (body_a == nullptr && body_b == nullptr) return;
  constexpr int kMaxContacts = 8;
  dContactGeom contact_geoms[kMaxContacts];
  const int max_contacts = std::min(kMaxContacts, model.physics.max_contacts_per_pair);
  const int n = dCollide(a, b, max_contacts, contact_geoms, sizeof(dContactGeom));
  if (n == 0) return;
  const auto* info_a = static_cast<const GeomInfo*>(dGeomGetData(a));
  const auto* info_b = static_cast<const GeomInfo*>(dGeomGetData(b));
  const double mu = 0.5 * (materials.Friction(info_a->material) + materials.Friction(info_b->material));
  // Point contacts carry no torsional friction, so a held object would pivot about the line
  // through its few pad contacts. A pad's area contact resists that twist: spinning friction
  // over the pad's effective radius.
  const bool pad_contact = info_a->material == Material::kFingerPad || info_b->material == Material::kFingerPad;
  for (int i = 0; i < n; ++i) {
    dContact contact{};
    contact.surface.mode = dContactApprox1 | dContactSoftERP | dContactSoftCFM;
    if (pad_contact) {
      contact.surface.mode |= dContactRolling;
      contact.surface.rhoN = mu * kPadContactRadius;
    }
    contact.surface.mu = mu;
    contact.surface.soft_erp = model.physics.contact_erp;
    contact.surface.soft_cfm = model.physics.contact_cfm;
    contact.geom = contact_geoms[i];
    dJointID joint = dJointCreateContact(world, contacts, &contact);
    dJointAttach(joint, body_a, body_b);
  }
}

bool PhysicsWorld::Impl::BodiesAreSane() const {
  const double max_linear = model.physics.runaway_linear_speed;
  const double max_angular = model.physics.runaway_angular_speed;
  for (dBodyID body : all_bodies) {
    const dReal* p = dBodyGetPosition(body);
    const dReal* v = dBodyGetLinearVel(body);
    const dReal* w = dBodyGetAngularVel(body);
    const double speed = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    const double spin = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    if (!std::isfinite(p[0] + p[1] + p[2]) || !(speed < max_linear) || !(spin < max_angular)) return false;
  }
  return true;
}

}  // namespace tavis::engine

// Shading of one ray packet's hits in structure-of-arrays form (Embree's packet layout: lane k of
// every array belongs to ray k). A scalar pass copies each hit's surface parameters into per-lane
// arrays (HitLanes::GatherHit); the loops over all K lanes that follow have no data-dependent
// branches, so the compiler vectorises them. Each lane's arithmetic is the scalar code's
// (surface_shading.h, lighting_model.h), operation for operation, so images stay byte-identical.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include <Eigen/Core>

#include "render/internal/env_scenes.h"
#include "render/internal/shape_mesh.h"
#include "render/internal/surface_shading.h"

namespace tavis::render::internal {

// `take_a ? a : b` as a bitwise blend. GCC moves the loads and divisions of a ?: operand into a
// branch and then cannot vectorise the loop (they might trap); a blend keeps the loop branch-free.
inline float Blend(bool take_a, float a, float b) {
  uint32_t bits_a;
  uint32_t bits_b;
  std::memcpy(&bits_a, &a, sizeof bits_a);
  std::memcpy(&bits_b, &b, sizeof bits_b);
  const uint32_t mask = 0u - static_cast<uint32_t>(take_a);
  const uint32_t bits = (bits_a & mask) | (bits_b & ~mask);
  float blended;
  std::memcpy(&blended, &bits, sizeof blended);
  return blended;
}

enum class LaneKind : int32_t {
  kInactive,  // outside the tile
  kMiss,      // the ray hit nothing: the dome
  kEmissive,  // flat colour, no lighting
  kDiffuse,   // lit by the dome and the distant light
};

// The surface parameters of each lane's hit. How a lane's local normal is found:
// round shapes (spheres, capsules, cylinder sides) normalise p - (0, 0, clamp(p.z, -h, h)) with
// h = round_half_length (0 for spheres, the capsule's half length, infinite for cylinder sides,
// where the clamp returns p.z); cylinder caps take (0, 0, sign of p.z); the rest (box faces,
// planes) take fixed_normal.
template <int K>
struct HitLanes {
  alignas(64) float frame[12][K];  // InstanceFrame::xfm of the hit instance
  alignas(64) float base[3][K];    // linear diffuse reflectance (or emissive colour, or the dome)
  alignas(64) float fixed_normal[3][K];
  alignas(64) float round_half_length[K];
  alignas(64) int32_t round[K];  // -1 where the normal is a round shape's, else 0
  alignas(64) int32_t cap[K];    // -1 on cylinder caps, else 0
  alignas(64) LaneKind kind[K];
  alignas(64) int32_t object_id[K];
  const SurfaceModel* labelled[K];  // the surface where it has a label, else nullptr

  // A lane without a surface (inactive or a miss): identity frame, upward normal, `colour`.
  void SetEmpty(int k, LaneKind lane_kind, const Eigen::Vector3f& colour) {
    for (int i = 0; i < 12; ++i) frame[i][k] = (i == 0 || i == 4 || i == 8) ? 1.0f : 0.0f;
    SetFixedNormal(k, Eigen::Vector3f::UnitZ());
    for (int c = 0; c < 3; ++c) base[c][k] = colour[c];
    kind[k] = lane_kind;
    object_id[k] = kBackgroundObjectId;
    labelled[k] = nullptr;
  }

  // Lane k hit triangle `primitive` of an instance with this surface, pose and reflectance `rgb`.
  void GatherHit(int k, const SurfaceModel& surface, const InstanceFrame& instance_frame, uint32_t primitive,
                 const Eigen::Vector3f& rgb) {
    for (int i = 0; i < 12; ++i) frame[i][k] = instance_frame.xfm[i];
    for (int c = 0; c < 3; ++c) base[c][k] = rgb[c];
    kind[k] = surface.appearance.emissive ? LaneKind::kEmissive : LaneKind::kDiffuse;
    object_id[k] = surface.object_id;
    labelled[k] = surface.appearance.label != LabelPattern::kNone ? &surface : nullptr;
    switch (surface.kind) {
      case ShapeKind::kBox: {
        const uint32_t face = primitive / 2;
        Eigen::Vector3f n = Eigen::Vector3f::Zero();
        n[kBoxFaceAxis[face]] = kBoxFaceSign[face];
        SetFixedNormal(k, n);
        return;
      }
      case ShapeKind::kCylinder:
        if (primitive >= surface.side_begin && primitive < surface.side_end) {
          SetRound(k, std::numeric_limits<float>::infinity());
        } else {
          SetFixedNormal(k, Eigen::Vector3f::UnitZ());
          cap[k] = -1;
        }
        return;
      case ShapeKind::kCapsule:
        SetRound(k, surface.capsule_half_length);
        return;
      case ShapeKind::kSphere:
        SetRound(k, 0.0f);
        return;
      case ShapeKind::kPlane:
        SetFixedNormal(k, Eigen::Vector3f::UnitZ());
        return;
    }
    SetFixedNormal(k, Eigen::Vector3f::UnitZ());
  }

 private:
  void SetFixedNormal(int k, const Eigen::Vector3f& n) {
    for (int c = 0; c < 3; ++c) fixed_normal[c][k] = n[c];
    round_half_length[k] = 0.0f;
    round[k] = 0;
    cap[k] = 0;
  }
  void SetRound(int k, float half_length) {
    SetFixedNormal(k, Eigen::Vector3f::UnitZ());
    round_half_length[k] = half_length;
    round[k] = -1;
  }
};

// Where each lane's ray hit and how the surface faces there.
template <int K>
struct HitGeometry {
  alignas(64) float p[3][K];        // world hit point
  alignas(64) float p_local[3][K];  // in the instance's frame
  alignas(64) float n_local[3][K];  // unit outward normal of the exact shape, local frame
  alignas(64) float n[3][K];        // world normal, turned towards the ray
  alignas(64) float cosine[K];      // max(0, n . to_light)
};

// Hit points, normals and the light's cosine for all lanes (LocalNormal, InstanceFrame and the
// lighting's cosine of the scalar path, lane-parallel). `dir` and `t` are the packet's ray
// directions and hit distances; lanes without a hit compute harmless values nobody reads.
// (__restrict: the arrays do not overlap; without it GCC needs more run-time overlap checks than
// it allows and leaves the loop scalar.)
template <int K>
void ComputeHitGeometry(const Eigen::Vector3f& origin, const float* __restrict dir_x, const float* __restrict dir_y,
                        const float* __restrict dir_z, const float* __restrict t, const Eigen::Vector3f& to_light,
                        const HitLanes<K>& __restrict lanes, HitGeometry<K>* __restrict out) {
  const float ox = origin.x(), oy = origin.y(), oz = origin.z();
  const float lx = to_light.x(), ly = to_light.y(), lz = to_light.z();
  const auto& f = lanes.frame;
  for (int k = 0; k < K; ++k) {
    const float px = ox + t[k] * dir_x[k];
    const float py = oy + t[k] * dir_y[k];
    const float pz = oz + t[k] * dir_z[k];
    out->p[0][k] = px;
    out->p[1][k] = py;
    out->p[2][k] = pz;
    // InstanceFrame::ToLocal.
    const float dx = px - f[9][k], dy = py - f[10][k], dz = pz - f[11][k];
    const float qx = f[0][k] * dx + f[1][k] * dy + f[2][k] * dz;
    const float qy = f[3][k] * dx + f[4][k] * dy + f[5][k] * dz;
    const float qz = f[6][k] * dx + f[7][k] * dy + f[8][k] * dz;
    out->p_local[0][k] = qx;
    out->p_local[1][k] = qy;
    out->p_local[2][k] = qz;
    // LocalNormal: round shapes (NormalizedOrUp of the offset from the nearest centre).
    const float h = lanes.round_half_length[k];
    const float upper = qz < h ? qz : h;
    const float centre_z = upper > -h ? upper : -h;
    const float rz = qz - centre_z;
    const float length = std::sqrt(qx * qx + qy * qy + rz * rz);
    const float unit_x = qx / length, unit_y = qy / length, unit_z = rz / length;
    const bool has_length = length > 1e-12f;
    const float round_x = Blend(has_length, unit_x, 0.0f);
    const float round_y = Blend(has_length, unit_y, 0.0f);
    const float round_z = Blend(has_length, unit_z, 1.0f);
    const float cap_z = Blend(qz >= 0.0f, 1.0f, -1.0f);
    const bool round = lanes.round[k] != 0;
    const float mx = Blend(round, round_x, lanes.fixed_normal[0][k]);
    const float my = Blend(round, round_y, lanes.fixed_normal[1][k]);
    const float mz = Blend(round, round_z, Blend(lanes.cap[k] != 0, cap_z, lanes.fixed_normal[2][k]));
    out->n_local[0][k] = mx;
    out->n_local[1][k] = my;
    out->n_local[2][k] = mz;
    // InstanceFrame::RotateToWorld, then face the viewer (a plane from below, a camera inside).
    float nx = f[0][k] * mx + f[3][k] * my + f[6][k] * mz;
    float ny = f[1][k] * mx + f[4][k] * my + f[7][k] * mz;
    float nz = f[2][k] * mx + f[5][k] * my + f[8][k] * mz;
    const bool behind = nx * dir_x[k] + ny * dir_y[k] + nz * dir_z[k] > 0.0f;
    nx = Blend(behind, -nx, nx);
    ny = Blend(behind, -ny, ny);
    nz = Blend(behind, -nz, nz);
    out->n[0][k] = nx;
    out->n[1][k] = ny;
    out->n[2][k] = nz;
    const float cosine = nx * lx + ny * ly + nz * lz;
    out->cosine[k] = Blend(0.0f < cosine, cosine, 0.0f);
  }
}

}  // namespace tavis::render::internal

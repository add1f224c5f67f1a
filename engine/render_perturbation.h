// What a cell's perturbations (docs/perturbations.md) change in what the cameras see, carried in
// the WorldModel so that every renderer made from the model (the policy's, episode videos,
// rollout and demo recorders, `tavis render`) shows the same perturbed views. Nothing here
// reaches the physics, the task or the scripted expert: a perturbed cell's episodes have the
// base cell's scenes and, for a policy that does not look, the base cell's motion. The defaults
// change nothing, so the base scene renders byte for byte as before.
#pragma once

#include <cstdint>

#include "engine/surface_texture.h"
#include "kinematics/pose.h"

namespace tavis::engine {

struct RenderPerturbation {
  // camera axis. The head camera's pose is offset in its own frame (x forward, y left, z up) and
  // rotated about its own axes (roll, pitch, yaw), as a mount knocked out of place would be; the
  // fixed camera is moved by fixed_offset_m (world frame), panned about the world's vertical
  // (yaw), tilted about its own left axis (pitch) and rolled about its optical axis (roll), as a
  // tripod set up elsewhere. A field of view scale multiplies the horizontal angle of view (the
  // focal length follows).
  Vec3 head_offset_m = Vec3::Zero();
  Vec3 head_rotation_deg = Vec3::Zero();
  Vec3 fixed_offset_m = Vec3::Zero();
  Vec3 fixed_rotation_deg = Vec3::Zero();
  double head_fov_scale = 1.0;
  double fixed_fov_scale = 1.0;

  // lighting axis. Both lights' intensities are scaled; the distant light's direction of travel
  // is turned about the world z axis (azimuth) and tilted toward the horizon (elevation, negative
  // lowers the sun); a colour temperature other than 0 tints both lights like a black body of
  // that temperature (6500 K is white).
  double light_intensity_scale = 1.0;
  double light_azimuth_deg = 0.0;
  double light_elevation_deg = 0.0;
  double colour_temperature_k = 0.0;

  // sensor axis, applied to the rendered RGB images (not depth or ids): a Gaussian blur of this
  // sigma in pixels, then Gaussian noise of this standard deviation in 8-bit levels, drawn per
  // (seed, episode, control tick, camera, pixel) from its own stream.
  double blur_sigma_px = 0.0;
  double noise_stddev = 0.0;
  uint64_t noise_seed = 0;  // the cell's seed (also keys the appearance axis's random colours)

  // appearance axis: procedural textures replacing the palette colour of the table (the static
  // part named "table"), the floor (the ground plane: all that surrounds the scene) and every
  // object flagged ObjectSpec::distractor. kNone leaves a surface as it is.
  SurfaceTexture table_texture;
  SurfaceTexture floor_texture;
  SurfaceTexture distractor_texture;

  bool moves_cameras() const {
    return !head_offset_m.isZero(0) || !head_rotation_deg.isZero(0) || !fixed_offset_m.isZero(0) ||
           !fixed_rotation_deg.isZero(0) || head_fov_scale != 1.0 || fixed_fov_scale != 1.0;
  }
  bool changes_lighting() const {
    return light_intensity_scale != 1.0 || light_azimuth_deg != 0.0 || light_elevation_deg != 0.0 ||
           colour_temperature_k != 0.0;
  }
  bool changes_images() const { return blur_sigma_px > 0.0 || noise_stddev > 0.0; }
  bool changes_surfaces() const {
    return table_texture.textured() || floor_texture.textured() || distractor_texture.textured();
  }
};

}  // namespace tavis::engine

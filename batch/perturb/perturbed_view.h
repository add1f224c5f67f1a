// How engine::RenderPerturbation (the camera, lighting and sensor perturbation axes,
// docs/perturbations.md) is applied to what SceneRender draws: the cameras' intrinsics and poses,
// the scene's lights, and the rendered RGB images. Each function is the identity for the default
// RenderPerturbation, so the base scene renders exactly as it did without them.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "engine/batch_state.h"
#include "engine/render_perturbation.h"
#include "render/camera.h"
#include "render/image_batch.h"
#include "render/scene_layout.h"

namespace tavis::batch::perturb {

// The camera's spec with its field of view scaled (head and fixed cameras; wrists unchanged).
// Throws std::invalid_argument naming the scale when the scaled angle is not in (0, 180) degrees.
render::CameraSpec PerturbedCameraSpec(render::CameraSpec spec, const engine::RenderPerturbation& perturbation);

// The pose offset a camera gets in its own frame (X_WC' = X_WC * offset): the head camera's
// mount offset and rotation; identity for the wrists and for the fixed camera (whose world pose
// is replaced instead, PerturbedFixedCameraPose).
RigidTransform CameraMountOffset(const std::string& camera, const engine::RenderPerturbation& perturbation);
RigidTransform PerturbedFixedCameraPose(const RigidTransform& X_WC, const engine::RenderPerturbation& perturbation);

// The lights scaled, turned and tinted.
void PerturbLighting(const engine::RenderPerturbation& perturbation, render::LightingSpec* lighting);

// Relative linear RGB of a black body at `kelvin`, normalised so 6500 K is (1, 1, 1) and every
// colour has the luminance of white (the tint changes hue, not brightness). Throws
// std::invalid_argument for a temperature outside [1000, 40000] K.
Eigen::Vector3f BlackBodyTint(double kelvin);

// Blurs, then adds noise to, the RGB image of every (env, camera) with enabled[env * cameras +
// camera] != 0 (camera_names: the images' cameras in order); the noise of a pixel is a function
// of (noise_seed, the env's episode index and control tick, the camera's name, pixel) only, so it repeats exactly for
// any thread count or slot.
void ApplySensorPerturbation(const engine::RenderPerturbation& perturbation, const engine::BatchState& state,
                             const std::vector<std::string>& camera_names, const std::vector<uint8_t>& enabled,
                             render::ImageBatch* images);
// The same for one env's images only (a per-slot render call: other slots' images belong to
// other threads).
void ApplySensorPerturbationToEnv(const engine::RenderPerturbation& perturbation, const engine::BatchState& state,
                                  const std::vector<std::string>& camera_names, const std::vector<uint8_t>& enabled,
                                  int env, render::ImageBatch* images);

}  // namespace tavis::batch::perturb

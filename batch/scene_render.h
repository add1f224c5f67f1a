// The bridge from the simulated world to the renderer. A render::SceneLayout is built once from
// the WorldModel (floor, static parts, objects, robot link shapes, gripper housings and finger
// pads, cameras); every rendered tick the instance and camera poses are filled from the
// BatchState by forward kinematics of the measured joint positions, so the images show exactly
// the state the physics produced, with the colours the task gave its objects (a cue card's, a
// light's). Object ids in the id buffer are object indices in the model.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "batch/perturb/perturbed_appearance.h"
#include "engine/batch_state.h"
#include "engine/world_model.h"
#include "kinematics/gripper_geometry.h"
#include "render/batch_renderer.h"
#include "render/image_batch.h"
#include "render/render_inputs.h"
#include "render/scene_layout.h"

namespace tavis::render {
class BatchRenderer;
}

namespace tavis::batch {

// The four TAVIS cameras (reference 2.1, 6.1, 6.2): head, fixed, left_wrist, right_wrist.
const std::vector<std::string>& SceneCameraNames();

struct CameraSettings {
  std::vector<std::string> cameras;  // from SceneCameraNames(); the images keep this order
  int width = 640;                   // the reference renders 640 x 480
  int height = 480;
  bool with_depth = false;
  bool with_object_id = false;
};

// Throws std::invalid_argument naming an unknown or repeated camera, or a non-positive size.
void ValidateCameraSettings(const CameraSettings& settings);

// "head,left_wrist" -> {"head", "left_wrist"}; throws std::invalid_argument naming an unknown
// or repeated name or an empty entry.
std::vector<std::string> ParseCameraList(const std::string& text);

class SceneRender {
 public:
  SceneRender(const engine::WorldModel& model, int num_envs, const CameraSettings& settings);
  ~SceneRender();
  SceneRender(const SceneRender&) = delete;
  SceneRender& operator=(const SceneRender&) = delete;

  int num_envs() const { return num_envs_; }
  const CameraSettings& settings() const { return settings_; }
  // Instances in order: floor, static parts, objects (object id = object index), robot link
  // shapes, then per arm the gripper housing and per jaw its pad and a visual finger link.
  const render::SceneLayout& layout() const;
  int num_cameras() const { return static_cast<int>(settings_.cameras.size()); }
  // Index of a camera in the images, -1 when it is not rendered.
  int CameraIndex(const std::string& name) const;

  // A disabled camera gives an all-zero image and traces no ray: blocked-clutter-pick-cube's
  // head view (reference 4.8). All cameras start enabled.
  void SetCameraEnabled(int env, int camera, bool enabled);
  bool camera_enabled(int env, int camera) const { return enabled_[Index(env, camera)] != 0; }

  // Renders every env with render_env[env] != 0 (num_envs flags) from the state; the other envs'
  // images are cleared to zero. Deterministic for any thread count; allocates nothing.
  void Render(const engine::BatchState& state, const uint8_t* render_env);
  // Renders env `env` alone from the state (idle threads may take some of its tiles); the other
  // envs' images are left as they are. Calls for distinct envs may run concurrently (not with
  // Render). The images are those Render draws for the env.
  render::RenderStats RenderEnv(const engine::BatchState& state, int env);

  const render::ImageBatch& images() const { return *images_; }
  // The instance poses (layout order) and camera poses (settings order) of env `env` at its last
  // Render, so that another renderer can draw exactly the same scene (bench/peer).
  const RigidTransform* instance_poses(int env) const {
    return X_WI_.data() + static_cast<std::size_t>(env) * sources_.size();
  }
  const RigidTransform* camera_poses(int env) const { return X_WC_.data() + Index(env, 0); }

 private:
  // Where an instance's pose comes from each tick.
  enum class Source : uint8_t { kStatic, kRobotShape, kFingerJaw, kObject };
  struct InstanceSource {
    Source source = Source::kStatic;
    int index = -1;     // link (kRobotShape, kBaseLink for the base), arm side (kFingerJaw), object
    double sign = 0.0;  // kFingerJaw: which jaw, along +- the closing axis
    // kStatic: the world pose; kRobotShape: the pose in the link; kFingerJaw: the pose in the IK
    // link with the jaws closed on the centre line (the gap is added along the closing axis).
    RigidTransform X_local = RigidTransform::Identity();
    perturb::TexturedSurface surface = perturb::TexturedSurface::kNone;  // what the appearance axis may texture
  };

  std::size_t Index(int env, int camera) const {
    return static_cast<std::size_t>(env) * settings_.cameras.size() + static_cast<std::size_t>(camera);
  }
  // Builds the layout and records where each instance's pose comes from.
  static render::SceneLayout BuildScene(const engine::WorldModel& model, const CameraSettings& settings,
                                        std::vector<InstanceSource>* sources, std::vector<int>* camera_mount);
  void FillEnv(const engine::BatchState& state, int env);
  render::RenderInputs Inputs() const;

  kinematics::RobotModel robot_;
  kinematics::GripperGeometry gripper_;
  int num_envs_ = 0;
  CameraSettings settings_;
  std::vector<InstanceSource> sources_;  // [instance]
  std::vector<int> camera_mount_;        // [camera]: robot camera index, -1 for the fixed camera
  std::unique_ptr<render::BatchRenderer> renderer_;
  std::unique_ptr<render::ImageBatch> images_;

  // Per-tick buffers, sized once.
  std::vector<RigidTransform> X_BL_;           // [env][link] link poses in the base frame
  std::vector<RigidTransform> X_WI_;           // [env][instance]
  std::vector<uint8_t> visible_;               // [env][instance]
  std::vector<Eigen::Vector3f> rgb_;           // [env][instance] the palette's, or the task's object colour
  std::vector<RigidTransform> X_WC_;           // [env][camera]
  std::vector<uint8_t> enabled_;               // [env][camera] the caller's blocked flags
  std::vector<uint8_t> tick_enabled_;          // [env][camera] enabled and rendered this call
  engine::RenderPerturbation perturbation_;    // the model's camera, lighting and sensor perturbations
  std::vector<RigidTransform> camera_offset_;  // [camera] its perturbed mount in its own frame
  perturb::AppearanceTextures appearance_;     // the model's appearance perturbation (textures)
};

}  // namespace tavis::batch

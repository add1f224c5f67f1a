#include "batch/scene_render.h"

#include <algorithm>
#include <sstream>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "batch/perturb/perturbed_view.h"
#include "kinematics/forward_kinematics.h"
#include "kinematics/gripper_geometry.h"
#include "render/batch_renderer.h"
#include "render/camera.h"
#include "render/palette.h"
#include "render/shape.h"

namespace tavis::batch {
namespace {

constexpr const char* kFixedCamera = "fixed";

std::string KnownCameras() {
  std::string names;
  for (const std::string& name : SceneCameraNames()) names += (names.empty() ? "" : ", ") + name;
  return names;
}

render::CameraSpec SpecOf(const std::string& name, const kinematics::RobotModel& robot, int width, int height,
                          int* mount) {
  if (name == kFixedCamera) {
    *mount = -1;
    return render::FixedCameraSpec(width, height);
  }
  *mount = robot.CameraIndex(name);
  const kinematics::CameraMount& camera = robot.cameras[static_cast<std::size_t>(*mount)];
  render::CameraSpec spec;
  spec.name = name;
  spec.width = width;
  spec.height = height;
  spec.focal_length_mm = camera.focal_length_mm;
  spec.near_m = camera.near_m;
  spec.far_m = camera.far_m;
  return spec;
}

}  // namespace

const std::vector<std::string>& SceneCameraNames() {
  static const std::vector<std::string> names = {"head", kFixedCamera, "left_wrist", "right_wrist"};
  return names;
}

void ValidateCameraSettings(const CameraSettings& settings) {
  const std::vector<std::string>& known = SceneCameraNames();
  for (std::size_t i = 0; i < settings.cameras.size(); ++i) {
    const std::string& name = settings.cameras[i];
    if (std::find(known.begin(), known.end(), name) == known.end()) {
      throw std::invalid_argument("unknown camera '" + name + "' (known: " + KnownCameras() + ")");
    }
    if (std::find(settings.cameras.begin(), settings.cameras.begin() + static_cast<std::ptrdiff_t>(i), name) !=
        settings.cameras.begin() + static_cast<std::ptrdiff_t>(i)) {
      throw std::invalid_argument("camera '" + name + "' is listed twice");
    }
  }
  if (settings.width < 1 || settings.height < 1) {
    throw std::invalid_argument("image size " + std::to_string(settings.width) + "x" + std::to_string(settings.height) +
                                " must be positive");
  }
}

std::vector<std::string> ParseCameraList(const std::string& text) {
  std::vector<std::string> cameras;
  std::istringstream in(text);
  for (std::string name; std::getline(in, name, ',');) {
    if (name.empty())
      throw std::invalid_argument("empty camera name in '" + text + "' (known: " + KnownCameras() + ")");
    cameras.push_back(name);
  }
  if (!text.empty() && text.back() == ',') {
    throw std::invalid_argument("empty camera name in '" + text + "' (known: " + KnownCameras() + ")");
  }
  CameraSettings check;
  check.cameras = cameras;
  ValidateCameraSettings(check);
  return cameras;
}

render::SceneLayout SceneRender::BuildScene(const engine::WorldModel& model, const CameraSettings& settings,
                                            std::vector<InstanceSource>* sources, std::vector<int>* camera_mount) {
  const kinematics::RobotModel& robot = model.robot;
  render::SceneLayout layout;
  auto add = [&](const render::ShapeGeometry& geometry, const std::string& look, int32_t object_id,
                 const InstanceSource& source) {
    layout.instances.push_back({geometry, render::PaletteAppearance(look), object_id});
    sources->push_back(source);
  };

  // The ground plane z = 0 (reference 2.1).
  add(render::MakePlane(), "floor", render::kBackgroundObjectId,
      {Source::kStatic, -1, 0.0, RigidTransform::Identity(), perturb::TexturedSurface::kFloor});
  for (const engine::StaticPart& part : model.static_parts) {
    add(part.shape, part.appearance, render::kBackgroundObjectId,
        {Source::kStatic, -1, 0.0, part.X_WS, perturb::SurfaceOfStaticPart(part)});
  }
  for (int object = 0; object < model.num_objects(); ++object) {
    const engine::ObjectSpec& spec = model.objects[static_cast<std::size_t>(object)];
    add(spec.shape, spec.appearance, object, {Source::kObject, object, 0.0, {}, perturb::SurfaceOfObject(spec)});
  }
  // Every link shape is drawn, the neck's too (physics leaves the kinematic head out).
  for (const kinematics::LinkShape& shape : robot.shapes) {
    add(shape.shape, "robot_link", render::kBackgroundObjectId, {Source::kRobotShape, shape.link, 0.0, shape.X_LS});
  }
  // Grippers as the physics builds them (kinematics/gripper_geometry.h): a housing fixed to the IK
  // link and two pads on either side of the pad centre along the closing axis. The physics has no
  // finger links between the housing and the pads, so drawn alone the pads float a few cm off
  // the housing; each jaw also gets a visual-only finger from the housing's bottom face down to
  // its pad's centre.
  const kinematics::GripperGeometry gripper(robot.gripper);
  const kinematics::GripperSpec& g = gripper.spec();
  for (kinematics::Side side : kinematics::kSides) {
    const int ik_link = robot.arm(side).ik_link;
    add(render::MakeBox(g.housing_size), "gripper", render::kBackgroundObjectId,
        {Source::kRobotShape, ik_link, 0.0, gripper.X_IkHousing()});
    for (const double sign : kinematics::kJawSigns) {
      add(render::MakeBox(g.pad_size), "gripper", render::kBackgroundObjectId,
          {Source::kFingerJaw, kinematics::Index(side), sign, MakeTransform(g.pad_center, Mat3::Identity())});
      if (gripper.visual_finger_length() > 0.0) {
        add(render::MakeBox(gripper.visual_finger_size()), "gripper", render::kBackgroundObjectId,
            {Source::kFingerJaw, kinematics::Index(side), sign,
             MakeTransform(gripper.visual_finger_centre(), Mat3::Identity())});
      }
    }
  }

  for (const std::string& name : settings.cameras) {
    int mount = -1;
    layout.cameras.push_back(perturb::PerturbedCameraSpec(SpecOf(name, robot, settings.width, settings.height, &mount),
                                                          model.view_perturbation));
    camera_mount->push_back(mount);
  }
  // The task's shadow light (multi-shelf-scan has its own); the dome light is shared.
  layout.lighting.distant_direction = model.lighting.distant_direction.cast<float>();
  layout.lighting.distant_intensity = static_cast<float>(model.lighting.distant_intensity);
  perturb::PerturbLighting(model.view_perturbation, &layout.lighting);
  return layout;
}

SceneRender::SceneRender(const engine::WorldModel& model, int num_envs, const CameraSettings& settings)
    : robot_(model.robot),
      gripper_(model.robot.gripper),
      num_envs_(num_envs),
      settings_(settings),
      perturbation_(model.view_perturbation) {
  ValidateCameraSettings(settings_);
  if (settings_.cameras.empty()) throw std::invalid_argument("SceneRender: no camera to render");
  if (num_envs_ < 1)
    throw std::invalid_argument("SceneRender: num_envs = " + std::to_string(num_envs_) + " must be positive");
  render::RenderOptions options;
  options.with_depth = settings_.with_depth;
  options.with_object_id = settings_.with_object_id;
  renderer_ = std::make_unique<render::BatchRenderer>(BuildScene(model, settings_, &sources_, &camera_mount_),
                                                      num_envs_, options);
  images_ = std::make_unique<render::ImageBatch>(renderer_->MakeImageBatch());

  const std::size_t envs = static_cast<std::size_t>(num_envs_);
  const std::size_t instances = sources_.size();
  X_BL_.assign(envs * static_cast<std::size_t>(robot_.num_links()), RigidTransform::Identity());
  X_WI_.assign(envs * instances, RigidTransform::Identity());
  visible_.assign(envs * instances, 1);
  rgb_.resize(envs * instances);
  X_WC_.assign(envs * settings_.cameras.size(), RigidTransform::Identity());
  enabled_.assign(envs * settings_.cameras.size(), 1);
  tick_enabled_.assign(envs * settings_.cameras.size(), 0);
  for (const std::string& name : settings_.cameras)
    camera_offset_.push_back(perturb::CameraMountOffset(name, perturbation_));
  std::vector<perturb::TexturedSurface> surfaces;
  for (const InstanceSource& source : sources_) surfaces.push_back(source.surface);
  appearance_ = perturb::AppearanceTextures(perturbation_, std::move(surfaces), num_envs_);
  // Static parts and the fixed camera never move: their poses are written once.
  for (std::size_t env = 0; env < envs; ++env) {
    for (std::size_t i = 0; i < instances; ++i) {
      if (sources_[i].source == Source::kStatic) X_WI_[env * instances + i] = sources_[i].X_local;
      rgb_[env * instances + i] = layout().instances[i].appearance.rgb;
    }
    for (int c = 0; c < num_cameras(); ++c) {
      if (camera_mount_[static_cast<std::size_t>(c)] < 0)
        X_WC_[Index(static_cast<int>(env), c)] =
            perturb::PerturbedFixedCameraPose(render::FixedCameraPose(), perturbation_);
    }
  }
}

SceneRender::~SceneRender() = default;

const render::SceneLayout& SceneRender::layout() const { return renderer_->layout(); }

int SceneRender::CameraIndex(const std::string& name) const {
  const auto it = std::find(settings_.cameras.begin(), settings_.cameras.end(), name);
  return it == settings_.cameras.end() ? -1 : static_cast<int>(it - settings_.cameras.begin());
}

void SceneRender::SetCameraEnabled(int env, int camera, bool enabled) {
  if (env < 0 || env >= num_envs_ || camera < 0 || camera >= num_cameras()) {
    throw std::out_of_range("SceneRender::SetCameraEnabled: env " + std::to_string(env) + ", camera " +
                            std::to_string(camera) + " out of range (" + std::to_string(num_envs_) + " envs, " +
                            std::to_string(num_cameras()) + " cameras)");
  }
  enabled_[Index(env, camera)] = enabled ? 1 : 0;
}

void SceneRender::FillEnv(const engine::BatchState& state, int env) {
  const std::size_t instances = sources_.size();
  const std::size_t first = static_cast<std::size_t>(env) * instances;
  RigidTransform* X_BL = &X_BL_[static_cast<std::size_t>(env) * static_cast<std::size_t>(robot_.num_links())];
  kinematics::ComputeLinkPoses(robot_, state.q_row(env), X_BL);
  // The base sits at root_world with no rotation (kinematics/robot_model.h).
  const RigidTransform X_WB = MakeTransform(robot_.root_world, Mat3::Identity());

  for (std::size_t i = 0; i < instances; ++i) {
    const InstanceSource& source = sources_[i];
    RigidTransform& X_WI = X_WI_[first + i];
    switch (source.source) {
      case Source::kStatic: break;
      case Source::kRobotShape:
        X_WI =
            source.index == kinematics::kBaseLink ? X_WB * source.X_local : X_WB * X_BL[source.index] * source.X_local;
        break;
      case Source::kFingerJaw: {
        // The jaws are drawn symmetric about the pad centre at the measured gap. In the physics
        // each jaw has its own slider but the state carries only their total gap, so when a grasp
        // has pushed one jaw further than the other (usually < 2 mm, rarely a few cm) the pads
        // are drawn shifted against the object they hold.
        const int side = source.index;
        const double gap = state.gripper_gap_row(env)[side];
        const Vec3 centre = source.X_local.translation() + gripper_.JawOffset(source.sign, gap);
        const int ik_link = robot_.arms[static_cast<std::size_t>(side)].ik_link;
        X_WI = X_WB * X_BL[ik_link] * MakeTransform(centre, Mat3::Identity());
        break;
      }
      case Source::kObject: {
        const double* pose = state.object_pose_row(env, source.index);
        X_WI = MakeTransform(Vec3(pose[0], pose[1], pose[2]),
                             Quat(pose[3], pose[4], pose[5], pose[6]).normalized().toRotationMatrix());
        visible_[first + i] = state.object_enabled_at(env, source.index);
        // A negative colour means the palette's (engine/batch_state.h).
        const float* rgb = state.object_rgb_row(env, source.index);
        rgb_[first + i] =
            rgb[0] >= 0.0f ? Eigen::Vector3f(rgb[0], rgb[1], rgb[2]) : layout().instances[i].appearance.rgb;
        break;
      }
    }
  }
  if (appearance_.active()) appearance_.ShowEpisode(env, state.episode[static_cast<std::size_t>(env)]);
  for (int c = 0; c < num_cameras(); ++c) {
    const int mount = camera_mount_[static_cast<std::size_t>(c)];
    if (mount >= 0) X_WC_[Index(env, c)] = X_WB * kinematics::CameraPose(robot_, mount, X_BL);
    if (mount >= 0 && perturbation_.moves_cameras())
      X_WC_[Index(env, c)] = X_WC_[Index(env, c)] * camera_offset_[static_cast<std::size_t>(c)];
  }
}

void SceneRender::Render(const engine::BatchState& state, const uint8_t* render_env) {
  tbb::parallel_for(0, num_envs_, [&](int env) {
    const bool rendered = render_env[env] != 0;
    for (int c = 0; c < num_cameras(); ++c) tick_enabled_[Index(env, c)] = rendered ? enabled_[Index(env, c)] : 0;
    if (rendered) FillEnv(state, env);
  });
  renderer_->Render(Inputs(), images_.get());
  perturb::ApplySensorPerturbation(perturbation_, state, settings_.cameras, tick_enabled_, images_.get());
}

render::RenderStats SceneRender::RenderEnv(const engine::BatchState& state, int env) {
  for (int c = 0; c < num_cameras(); ++c) tick_enabled_[Index(env, c)] = enabled_[Index(env, c)];
  FillEnv(state, env);
  const render::RenderStats stats = renderer_->RenderEnv(env, Inputs(), images_.get());
  perturb::ApplySensorPerturbationToEnv(perturbation_, state, settings_.cameras, tick_enabled_, env, images_.get());
  return stats;
}

render::RenderInputs SceneRender::Inputs() const {
  render::RenderInputs inputs;
  inputs.X_WI = X_WI_;
  inputs.instance_visible = visible_;
  inputs.instance_rgb = rgb_;
  inputs.instance_texture = appearance_.textures();  // empty without an appearance level
  inputs.X_WC = X_WC_;
  inputs.camera_enabled = tick_enabled_;
  return inputs;
}

}  // namespace tavis::batch

#include "render/internal/env_scenes.h"

namespace tavis::render::internal {
namespace {

bool IsFinitePose(const RigidTransform& X) { return X.matrix().topRows<3>().allFinite(); }

void FillFrame(const RigidTransform& X, InstanceFrame* frame) {
  for (int column = 0; column < 4; ++column) {
    for (int row = 0; row < 3; ++row) frame->xfm[3 * column + row] = static_cast<float>(X.matrix()(row, column));
  }
}

}  // namespace

EnvScenes::EnvScenes(RTCDevice device, const ShapeLibrary& shapes, int num_envs, int n_instances)
    : n_instances_(n_instances) {
  const std::size_t count = static_cast<std::size_t>(num_envs) * static_cast<std::size_t>(n_instances);
  frames_.resize(count);
  enabled_.assign(count, 1);
  for (int env = 0; env < num_envs; ++env) {
    ScenePtr scene(rtcNewScene(device));
    // Rebuilt every rendered tick from a few dozen instances: favour build speed.
    rtcSetSceneFlags(scene.get(), RTC_SCENE_FLAG_DYNAMIC);
    rtcSetSceneBuildQuality(scene.get(), RTC_BUILD_QUALITY_LOW);
    for (int instance = 0; instance < n_instances; ++instance) {
      GeometryPtr geometry(rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE));
      rtcSetGeometryInstancedScene(geometry.get(), shapes.scene_of_instance(instance));
      InstanceFrame& frame = frames_[instances_.size()];
      FillFrame(RigidTransform::Identity(), &frame);
      rtcSetGeometryTransform(geometry.get(), 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, frame.xfm);
      rtcCommitGeometry(geometry.get());
      // The geometry id is the instance index: hits report it as instID[0].
      rtcAttachGeometryByID(scene.get(), geometry.get(), static_cast<unsigned int>(instance));
      instances_.push_back(std::move(geometry));
    }
    rtcCommitScene(scene.get());
    scenes_.push_back(std::move(scene));
  }
  ThrowIfEmbreeError(device, "creating the per-env instance scenes");
}

void EnvScenes::Update(int env, const RenderInputs& inputs) {
  const std::size_t first = static_cast<std::size_t>(env) * static_cast<std::size_t>(n_instances_);
  for (std::size_t i = first; i < first + static_cast<std::size_t>(n_instances_); ++i) {
    RTCGeometry geometry = instances_[i].get();
    const RigidTransform& X_WI = inputs.X_WI[i];
    const bool visible = (inputs.instance_visible.empty() || inputs.instance_visible[i] != 0) && IsFinitePose(X_WI);
    if (visible) {
      FillFrame(X_WI, &frames_[i]);
      rtcSetGeometryTransform(geometry, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, frames_[i].xfm);
      rtcCommitGeometry(geometry);
      if (enabled_[i] == 0) rtcEnableGeometry(geometry);
    } else if (enabled_[i] != 0) {
      rtcDisableGeometry(geometry);
    }
    enabled_[i] = visible ? 1 : 0;
  }
  rtcCommitScene(scenes_[static_cast<std::size_t>(env)].get());
}

}  // namespace tavis::render::internal

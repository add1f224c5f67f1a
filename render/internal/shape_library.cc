#include "render/internal/shape_library.h"

#include <algorithm>
#include <cstring>

#include "render/internal/embree_device.h"
#include "render/internal/shape_mesh.h"

namespace tavis::render::internal {
namespace {

ScenePtr BuildShapeScene(RTCDevice device, const ShapeMesh& mesh) {
  const GeometryPtr geometry(rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE));
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry.get(), RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.vertex_count()));
  auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
      geometry.get(), RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), mesh.triangle_count()));
  ThrowIfEmbreeError(device, "allocating a shape mesh");
  std::memcpy(vertices, mesh.vertices.data(), mesh.vertices.size() * sizeof(float));
  std::memcpy(indices, mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t));
  rtcCommitGeometry(geometry.get());

  ScenePtr scene(rtcNewScene(device));
  // Built once and traced by every ray of every env: spend time on a good tree.
  rtcSetSceneBuildQuality(scene.get(), RTC_BUILD_QUALITY_HIGH);
  rtcAttachGeometry(scene.get(), geometry.get());
  rtcCommitScene(scene.get());
  ThrowIfEmbreeError(device, "building a shape BVH");
  return scene;
}

}  // namespace

ShapeLibrary::ShapeLibrary(RTCDevice device, const std::vector<InstanceSpec>& instances) {
  std::vector<ShapeGeometry> unique_shapes;
  std::vector<ShapeMesh> meshes;
  for (const InstanceSpec& instance : instances) {
    const auto found = std::find(unique_shapes.begin(), unique_shapes.end(), instance.geometry);
    const int shape = static_cast<int>(found - unique_shapes.begin());
    if (found == unique_shapes.end()) {
      unique_shapes.push_back(instance.geometry);
      meshes.push_back(TessellateShape(instance.geometry));
      shape_scenes_.push_back(BuildShapeScene(device, meshes.back()));
    }
    shape_of_instance_.push_back(shape);
    surfaces_.push_back(MakeSurfaceModel(instance, meshes[static_cast<std::size_t>(shape)]));
  }
}

}  // namespace tavis::render::internal

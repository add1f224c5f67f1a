// The process-wide Embree device and owning handles for Embree objects. One device, created
// with the default config (docs/architecture.md, Design 6): a "threads=N" config string would cap TBB
// parallelism for the whole process.
#pragma once

#include <memory>

#include <embree3/rtcore.h>

namespace tavis::render::internal {

// Created on first use, released at exit. Throws std::runtime_error if Embree cannot start.
RTCDevice SharedEmbreeDevice();

// Throws std::runtime_error naming `operation` and the Embree error if one is pending.
void ThrowIfEmbreeError(RTCDevice device, const char* operation);

struct SceneReleaser {
  void operator()(RTCScene scene) const { rtcReleaseScene(scene); }
};
struct GeometryReleaser {
  void operator()(RTCGeometry geometry) const { rtcReleaseGeometry(geometry); }
};
// Owning handles, so that a constructor that throws half-way releases what it built.
using ScenePtr = std::unique_ptr<RTCSceneTy, SceneReleaser>;
using GeometryPtr = std::unique_ptr<RTCGeometryTy, GeometryReleaser>;

}  // namespace tavis::render::internal

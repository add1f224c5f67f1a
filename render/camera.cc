#include "render/camera.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace tavis::render {

CameraIntrinsics IntrinsicsOf(const CameraSpec& camera) {
  CameraIntrinsics intrinsics;
  intrinsics.fx = camera.focal_length_mm / camera.horizontal_aperture_mm * camera.width;
  intrinsics.fy = intrinsics.fx;
  intrinsics.cx = 0.5 * camera.width;
  intrinsics.cy = 0.5 * camera.height;
  return intrinsics;
}

PixelProjection ProjectWorldPoint(const CameraSpec& camera, const RigidTransform& X_WC, const Vec3& p_W) {
  const Vec3 p_C = X_WC.inverse(Eigen::Isometry) * p_W;
  const CameraIntrinsics k = IntrinsicsOf(camera);
  PixelProjection projection;
  projection.depth = p_C.x();
  projection.u = k.cx - k.fx * p_C.y() / p_C.x();
  projection.v = k.cy - k.fy * p_C.z() / p_C.x();
  return projection;
}

bool IsVisibleInImage(const CameraSpec& camera, const PixelProjection& projection) {
  return projection.depth >= camera.near_m && projection.depth <= camera.far_m && projection.u >= 0.0 &&
         projection.u < camera.width && projection.v >= 0.0 && projection.v < camera.height;
}

void ValidateCamera(const CameraSpec& camera) {
  auto fail = [&](const char* field, double value, const char* requirement) {
    std::ostringstream message;
    message << "camera '" << camera.name << "': " << field << " = " << value << " " << requirement;
    throw std::invalid_argument(message.str());
  };
  if (camera.name.empty()) throw std::invalid_argument("camera with an empty name");
  if (camera.width <= 0) fail("width", camera.width, "must be positive");
  if (camera.height <= 0) fail("height", camera.height, "must be positive");
  if (!std::isfinite(camera.focal_length_mm) || camera.focal_length_mm <= 0.0)
    fail("focal_length_mm", camera.focal_length_mm, "must be positive and finite");
  if (!std::isfinite(camera.horizontal_aperture_mm) || camera.horizontal_aperture_mm <= 0.0)
    fail("horizontal_aperture_mm", camera.horizontal_aperture_mm, "must be positive and finite");
  if (!std::isfinite(camera.near_m) || camera.near_m <= 0.0)
    fail("near_m", camera.near_m, "must be positive and finite");
  if (!std::isfinite(camera.far_m) || camera.far_m <= camera.near_m)
    fail("far_m", camera.far_m, "must be finite and beyond near_m");
}

RigidTransform CameraLookAt(const Vec3& eye, const Vec3& target, const Vec3& up) {
  const Vec3 view = target - eye;
  const Vec3 side = up.cross(view);
  if (!view.allFinite() || view.norm() < 1e-9 || side.norm() < 1e-9 * view.norm()) {
    std::ostringstream message;
    message << "CameraLookAt: eye (" << eye.transpose() << "), target (" << target.transpose() << ") and up ("
            << up.transpose() << ") do not define a view";
    throw std::invalid_argument(message.str());
  }
  Mat3 R;
  R.col(0) = view.normalized();         // forward
  R.col(1) = side.normalized();         // image-left
  R.col(2) = R.col(0).cross(R.col(1));  // image-up
  return MakeTransform(eye, R);
}

namespace {

CameraSpec MakeSpec(const std::string& name, int width, int height, double focal_mm, double near_m, double far_m) {
  CameraSpec camera;
  camera.name = name;
  camera.width = width;
  camera.height = height;
  camera.focal_length_mm = focal_mm;
  camera.near_m = near_m;
  camera.far_m = far_m;
  return camera;
}

}  // namespace

CameraSpec HeadCameraSpec(int width, int height) { return MakeSpec("head", width, height, 15.0, 0.15, 10.0); }

CameraSpec WristCameraSpec(const std::string& name, int width, int height) {
  return MakeSpec(name, width, height, 21.0, 0.10, 1.0);
}

CameraSpec FixedCameraSpec(int width, int height) { return MakeSpec("fixed", width, height, 6.05, 0.1, 5.0); }

RigidTransform FixedCameraPose() {
  return MakeTransform(Vec3(0.2, 0.0, 1.43),
                       QuatFromWxyz(0.9238795, 0.0, 0.3826834, 0.0).normalized().toRotationMatrix());
}

}  // namespace tavis::render

// Pinhole cameras: specification, intrinsics, world-to-pixel projection, and the reference
// benchmark's camera models (reference spec §2.1, §6.1, §6.2).
//
// Camera frame C uses IsaacLab's "world" convention: the camera looks along its local +X, +Z is
// image-up and +Y is image-left. Pixel coordinates (u, v) are continuous: u grows to the right,
// v grows downwards, and pixel (row r, column c) covers [c, c+1) x [r, r+1), so its centre is
// (c + 0.5, r + 0.5). The principal point is the image centre (width/2, height/2).
#pragma once

#include <string>

#include "kinematics/pose.h"

namespace tavis::render {

inline constexpr double kHorizontalApertureMm = 20.955;

struct CameraSpec {
  std::string name;
  int width = 640;
  int height = 480;
  double focal_length_mm = 15.0;
  double horizontal_aperture_mm = kHorizontalApertureMm;
  double near_m = 0.1;  // clipping planes, as distances along the optical axis
  double far_m = 10.0;
};

// Square pixels: fx = fy = focal / horizontal aperture * width.
struct CameraIntrinsics {
  double fx = 0.0;
  double fy = 0.0;
  double cx = 0.0;
  double cy = 0.0;
};

CameraIntrinsics IntrinsicsOf(const CameraSpec& camera);

struct PixelProjection {
  double u = 0.0;
  double v = 0.0;
  double depth = 0.0;  // distance along the optical axis (camera-frame x); <= 0 behind the camera
};

// Projection of world point p_W through a camera at pose X_WC. Only meaningful for depth > 0.
PixelProjection ProjectWorldPoint(const CameraSpec& camera, const RigidTransform& X_WC, const Vec3& p_W);

// True when the projection lands inside the image and between the clipping planes.
bool IsVisibleInImage(const CameraSpec& camera, const PixelProjection& projection);

// Throws std::invalid_argument naming the camera and the value: empty name, non-positive
// resolution, focal length or aperture, near <= 0, far <= near, or a non-finite number.
void ValidateCamera(const CameraSpec& camera);

// Camera pose at `eye` looking at `target` with image-up as close as possible to `up`. Throws
// std::invalid_argument when eye == target or the view direction is parallel to `up`.
RigidTransform CameraLookAt(const Vec3& eye, const Vec3& target, const Vec3& up = Vec3::UnitZ());

// The reference benchmark's cameras at any resolution (640x480 in the reference).
CameraSpec HeadCameraSpec(int width = 640, int height = 480);  // 15 mm, clip 0.15-10 m
CameraSpec WristCameraSpec(const std::string& name, int width = 640,
                           int height = 480);                   // 21 mm, clip 0.10-1.0 m
CameraSpec FixedCameraSpec(int width = 640, int height = 480);  // 6.05 mm, clip 0.1-5.0 m

// World pose of the fixed workspace camera in the env frame: (0.2, 0, 1.43), pitched 45 deg down.
RigidTransform FixedCameraPose();

}  // namespace tavis::render

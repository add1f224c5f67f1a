#include "batch/camera_protocol.h"

#include <stdexcept>

namespace tavis::batch {

CameraProtocol ParseCameraProtocol(const std::string& text) {
  if (text == "head" || text == "headcam") return CameraProtocol::kHead;
  if (text == "fixed" || text == "fixedcam") return CameraProtocol::kFixed;
  throw std::invalid_argument("unknown camera protocol '" + text + "' (known: head, fixed)");
}

const char* ToString(CameraProtocol protocol) { return protocol == CameraProtocol::kHead ? "head" : "fixed"; }

std::vector<std::string> ProtocolCameras(const std::vector<std::string>& policy_cameras, CameraProtocol protocol) {
  std::vector<std::string> cameras = policy_cameras;
  if (protocol == CameraProtocol::kHead) return cameras;
  for (std::string& camera : cameras) {
    if (camera == "head") camera = "fixed";
  }
  return cameras;
}

void ApplyToAction(CameraProtocol protocol, kinematics::Action& action) {
  if (protocol == CameraProtocol::kHead) return;
  action[kinematics::action::kNeckRoll] = 0.0;
  action[kinematics::action::kNeckPitch] = 0.0;
  action[kinematics::action::kNeckYaw] = 0.0;
}

}  // namespace tavis::batch

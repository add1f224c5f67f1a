#include "batch/camera_protocol.h"

#include <stdexcept>

namespace tavis::batch {

CameraProtocol ParseCameraProtocol(const std::string& text) {
  if (text == "head" || text == "headcam") return CameraProtocol::kHead;
  if (text == "fixed" || text == "fixedcam") return CameraProtocol::kFixed;
  if (text == "head-only") return CameraProtocol::kHeadOnly;
  if (text == "wrists-only") return CameraProtocol::kWristsOnly;
  if (text == "fixed-only") return CameraProtocol::kFixedOnly;
  throw std::invalid_argument("unknown camera protocol '" + text +
                              "' (known: head, fixed, head-only, wrists-only, fixed-only)");
}

const char* ToString(CameraProtocol protocol) {
  switch (protocol) {
    case CameraProtocol::kHead: return "head";
    case CameraProtocol::kFixed: return "fixed";
    case CameraProtocol::kHeadOnly: return "head-only";
    case CameraProtocol::kWristsOnly: return "wrists-only";
    case CameraProtocol::kFixedOnly: return "fixed-only";
  }
  return "head";
}

const std::vector<std::string>& CameraProtocolNames() {
  static const std::vector<std::string> names = {"head", "fixed", "head-only", "wrists-only", "fixed-only"};
  return names;
}

bool UsesFixedView(CameraProtocol protocol) {
  return protocol == CameraProtocol::kFixed || protocol == CameraProtocol::kFixedOnly;
}

std::vector<std::string> ProtocolCameras(const std::vector<std::string>& policy_cameras, CameraProtocol protocol) {
  std::vector<std::string> cameras = policy_cameras;
  if (!UsesFixedView(protocol)) return cameras;
  for (std::string& camera : cameras) {
    if (camera == "head") camera = "fixed";
  }
  return cameras;
}

std::vector<std::string> ProtocolBlackCameras(CameraProtocol protocol) {
  switch (protocol) {
    case CameraProtocol::kHeadOnly:
    case CameraProtocol::kFixedOnly: return {"left_wrist", "right_wrist"};
    case CameraProtocol::kWristsOnly: return {"head"};
    case CameraProtocol::kHead:
    case CameraProtocol::kFixed: return {};
  }
  return {};
}

void ApplyToAction(CameraProtocol protocol, kinematics::Action& action) {
  if (!UsesFixedView(protocol)) return;
  action[kinematics::action::kNeckRoll] = 0.0;
  action[kinematics::action::kNeckPitch] = 0.0;
  action[kinematics::action::kNeckYaw] = 0.0;
}

}  // namespace tavis::batch

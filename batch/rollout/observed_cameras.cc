#include "batch/rollout/observed_cameras.h"

namespace tavis::batch::rollout {

std::vector<std::string> ObservedCameras(const std::vector<std::string>& policy_cameras, CameraProtocol protocol) {
  // The observation contract's cameras (docs/observation.md).
  static const std::vector<std::string> contract = {"head", "left_wrist", "right_wrist"};
  return ProtocolCameras(policy_cameras.empty() ? contract : policy_cameras, protocol);
}

}  // namespace tavis::batch::rollout

// The cameras a rollout is seen through: those the policy sees under the camera protocol, or for
// a policy that takes no images (the scripted expert) those the observation contract gives a
// served policy (head and wrists, the fixed camera for the head under `fixed`).
#pragma once

#include <string>
#include <vector>

#include "batch/camera_protocol.h"

namespace tavis::batch::rollout {

std::vector<std::string> ObservedCameras(const std::vector<std::string>& policy_cameras, CameraProtocol protocol);

}  // namespace tavis::batch::rollout

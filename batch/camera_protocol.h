// The benchmark's paired comparison (reference 9.2, 10.2): under `head` the policy sees the head
// camera and moves it (GALT is computed); under `fixed` it sees the fixed scene camera instead,
// its neck actions (dims 14-16) are zeroed before stepping, the neck entries of its
// observation.state are zeroed (ProprioceptionBatch), and no GALT is computed. Episode i has the
// same scene under both, so cells pair.
#pragma once

#include <string>
#include <vector>

#include "kinematics/action.h"

namespace tavis::batch {

enum class CameraProtocol { kHead, kFixed };

// "head" or "fixed" (the reference's "headcam" and "fixedcam" too); throws std::invalid_argument
// naming the value and the accepted ones.
CameraProtocol ParseCameraProtocol(const std::string& text);
const char* ToString(CameraProtocol protocol);

// The cameras a policy receives under the protocol: its own list, with the head camera replaced
// by the fixed camera under `fixed`.
std::vector<std::string> ProtocolCameras(const std::vector<std::string>& policy_cameras, CameraProtocol protocol);

// Applies the protocol to an action before it is stepped: under `fixed` the neck entries are 0.
void ApplyToAction(CameraProtocol protocol, kinematics::Action& action);

}  // namespace tavis::batch

// The benchmark's paired comparison (reference 9.2, 10.2), and camera sets beside it. Under
// `head` the policy sees the head camera and moves it (GALT is computed); under `fixed` it sees
// the fixed scene camera instead, its neck actions (dims 14-16) are zeroed before stepping, the
// neck entries of its observation.state are zeroed (ProprioceptionBatch), and no GALT is
// computed. The camera sets keep one of those two views and black out some of the policy's
// images (all zero, as a task's black camera; the camera still moves):
//   head-only    head, the wrist images black
//   wrists-only  head rules (the head moves, GALT computed), the head image black
//   fixed-only   fixed rules, the wrist images black
// `head` is head + wrists and `fixed` is fixed + wrists. Episode i has the same scene under all,
// so cells pair episode by episode.
#pragma once

#include <string>
#include <vector>

#include "kinematics/action.h"

namespace tavis::batch {

enum class CameraProtocol { kHead, kFixed, kHeadOnly, kWristsOnly, kFixedOnly };

// "head", "fixed" (the reference's "headcam" and "fixedcam" too), "head-only", "wrists-only" or
// "fixed-only"; throws std::invalid_argument naming the value and the accepted ones.
CameraProtocol ParseCameraProtocol(const std::string& text);
const char* ToString(CameraProtocol protocol);
// Every protocol's name, in the order above.
const std::vector<std::string>& CameraProtocolNames();

// True when the protocol shows the fixed camera in place of the head's (fixed, fixed-only): the
// neck is held still and no GALT is computed.
bool UsesFixedView(CameraProtocol protocol);

// The cameras a policy receives under the protocol: its own list, with the head camera replaced
// by the fixed camera under a fixed view.
std::vector<std::string> ProtocolCameras(const std::vector<std::string>& policy_cameras, CameraProtocol protocol);

// The cameras (SceneCameraNames) whose images the protocol blacks out.
std::vector<std::string> ProtocolBlackCameras(CameraProtocol protocol);

// Applies the protocol to an action before it is stepped: under a fixed view the neck entries are 0.
void ApplyToAction(CameraProtocol protocol, kinematics::Action& action);

}  // namespace tavis::batch

#include "batch/observation_contract.h"

#include <stdexcept>

namespace tavis::batch::contract {
namespace {

constexpr const char* kImagePrefix = "observation.images.";

struct CameraName {
  const char* camera;
  const char* name;
};
constexpr CameraName kCameraNames[] = {
    {"head", "OBS_HEAD"}, {"fixed", "OBS_FIXED"}, {"left_wrist", "OBS_WRIST_LEFT"}, {"right_wrist", "OBS_WRIST_RIGHT"}};

}  // namespace

std::string CameraImageName(const std::string& camera) {
  for (const CameraName& entry : kCameraNames) {
    if (camera == entry.camera) return entry.name;
  }
  throw std::invalid_argument("no image key for camera '" + camera + "' (known: head, fixed, left_wrist, right_wrist)");
}

std::string CameraImageKey(const std::string& camera) { return kImagePrefix + CameraImageName(camera); }

std::string CameraOfImageKey(const std::string& key) {
  for (const CameraName& entry : kCameraNames) {
    if (key == kImagePrefix + std::string(entry.name)) return entry.camera;
  }
  return "";
}

}  // namespace tavis::batch::contract

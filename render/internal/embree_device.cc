#include "render/internal/embree_device.h"

#include <stdexcept>
#include <string>

namespace tavis::render::internal {
namespace {

const char* ErrorName(RTCError error) {
  switch (error) {
    case RTC_ERROR_NONE: return "no error";
    case RTC_ERROR_UNKNOWN: return "unknown error";
    case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
    case RTC_ERROR_CANCELLED: return "cancelled";
  }
  return "unrecognised error";
}

class DeviceHolder {
 public:
  DeviceHolder() : device_(rtcNewDevice(nullptr)) {
    if (device_ == nullptr) {
      throw std::runtime_error(std::string("Embree: rtcNewDevice failed: ") + ErrorName(rtcGetDeviceError(nullptr)));
    }
  }
  ~DeviceHolder() { rtcReleaseDevice(device_); }
  DeviceHolder(const DeviceHolder&) = delete;
  DeviceHolder& operator=(const DeviceHolder&) = delete;

  RTCDevice get() const { return device_; }

 private:
  RTCDevice device_;
};

}  // namespace

RTCDevice SharedEmbreeDevice() {
  static const DeviceHolder holder;
  return holder.get();
}

void ThrowIfEmbreeError(RTCDevice device, const char* operation) {
  const RTCError error = rtcGetDeviceError(device);
  if (error != RTC_ERROR_NONE) throw std::runtime_error(std::string("Embree: ") + operation + ": " + ErrorName(error));
}

}  // namespace tavis::render::internal

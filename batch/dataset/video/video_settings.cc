#include "batch/dataset/video/video_settings.h"

#include <stdexcept>

namespace tavis::batch::dataset::video {
namespace {

[[noreturn]] void Reject(const std::string& path, const std::string& problem) {
  throw std::invalid_argument("video " + path + ": " + problem);
}

void RequireEvenPositive(const std::string& path, const char* name, int value) {
  if (value <= 0) Reject(path, std::string(name) + " " + std::to_string(value) + " must be positive");
  if (value % 2 != 0) {
    Reject(path, std::string(name) + " " + std::to_string(value) + " is odd; yuv420p needs even dimensions");
  }
}

}  // namespace

std::string VideoCodecName(VideoCodec codec) { return codec == VideoCodec::kAv1 ? "av1" : "h264"; }

VideoCodec ParseVideoCodec(const std::string& name) {
  if (name == "h264") return VideoCodec::kH264;
  if (name == "av1" || name == "libsvtav1") return VideoCodec::kAv1;
  throw std::invalid_argument("unknown video codec \"" + name + "\" (expected h264 or av1)");
}

void ValidateVideoSettings(const VideoSettings& settings, const std::string& path) {
  RequireEvenPositive(path, "width", settings.width);
  RequireEvenPositive(path, "height", settings.height);
  if (settings.codec == VideoCodec::kAv1 && (settings.width < 64 || settings.height < 64)) {
    Reject(path, "av1 frames of " + std::to_string(settings.width) + "x" + std::to_string(settings.height) +
                     " are too small; SVT-AV1 needs at least 64x64");
  }
  if (settings.fps <= 0) Reject(path, "fps " + std::to_string(settings.fps) + " must be positive");
  if (settings.gop <= 0) Reject(path, "gop " + std::to_string(settings.gop) + " must be positive");
  const int max_crf = settings.codec == VideoCodec::kAv1 ? 63 : 51;
  if (settings.crf < -1 || settings.crf > max_crf) {
    Reject(path, "crf " + std::to_string(settings.crf) + " is outside -1 (default) to " + std::to_string(max_crf));
  }
  if (settings.av1_preset < 0 || settings.av1_preset > 13) {
    Reject(path, "av1_preset " + std::to_string(settings.av1_preset) + " is outside 0 to 13");
  }
}

}  // namespace tavis::batch::dataset::video

#include "batch/dataset/video/video_settings.h"

#include <stdexcept>
#include <utility>

namespace tavis::batch::dataset::video {
namespace {

// The problem with a width or height, "" when there is none.
std::string EvenPositiveProblem(const char* name, int value) {
  if (value <= 0) return std::string(name) + " " + std::to_string(value) + " must be positive";
  if (value % 2 != 0) return std::string(name) + " " + std::to_string(value) + " is odd; yuv420p needs even dimensions";
  return "";
}

}  // namespace

std::string VideoCodecName(VideoCodec codec) { return codec == VideoCodec::kAv1 ? "av1" : "h264"; }

VideoCodec ParseVideoCodec(const std::string& name) {
  if (name == "h264") return VideoCodec::kH264;
  if (name == "av1" || name == "libsvtav1") return VideoCodec::kAv1;
  throw std::invalid_argument("unknown video codec \"" + name + "\" (expected h264 or av1)");
}

std::string VideoSettingsProblem(const VideoSettings& settings) {
  for (const auto& [name, value] :
       {std::pair<const char*, int>{"width", settings.width}, {"height", settings.height}}) {
    const std::string problem = EvenPositiveProblem(name, value);
    if (!problem.empty()) return problem;
  }
  if (settings.codec == VideoCodec::kAv1 && (settings.width < 64 || settings.height < 64)) {
    return "av1 frames of " + std::to_string(settings.width) + "x" + std::to_string(settings.height) +
           " are too small; SVT-AV1 needs at least 64x64";
  }
  if (settings.fps <= 0) return "fps " + std::to_string(settings.fps) + " must be positive";
  if (settings.gop <= 0) return "gop " + std::to_string(settings.gop) + " must be positive";
  const int max_crf = settings.codec == VideoCodec::kAv1 ? 63 : 51;
  if (settings.crf < -1 || settings.crf > max_crf) {
    return "crf " + std::to_string(settings.crf) + " is outside -1 (default) to " + std::to_string(max_crf);
  }
  if (settings.av1_preset < 0 || settings.av1_preset > 13) {
    return "av1_preset " + std::to_string(settings.av1_preset) + " is outside 0 to 13";
  }
  return "";
}

void ValidateVideoSettings(const VideoSettings& settings, const std::string& path) {
  const std::string problem = VideoSettingsProblem(settings);
  if (!problem.empty()) throw std::invalid_argument("video " + path + ": " + problem);
}

}  // namespace tavis::batch::dataset::video

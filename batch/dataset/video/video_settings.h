// Video stream settings: the codec, frame size, frame rate and encoder knobs of one mp4 camera
// stream. Validation happens up front, so a bad setting fails before any file is created.
#pragma once

#include <string>

namespace tavis::batch::dataset::video {

enum class VideoCodec {
  kH264,  // libx264: decodes everywhere (OpenCV included); the default
  kAv1,   // libsvtav1 with LeRobot's defaults (preset 12, crf 30)
};

struct VideoSettings {
  int width = 0;   // pixels; even, as yuv420p halves the chroma planes
  int height = 0;  // pixels; even
  int fps = 0;     // constant frame rate; frame k is shown at exactly k / fps seconds
  VideoCodec codec = VideoCodec::kH264;
  int gop = 2;                           // keyframe interval in frames (LeRobot's g=2: cheap random access)
  int crf = -1;                          // quality; -1 picks the codec's default (h264 23, av1 30)
  std::string h264_preset = "veryfast";  // x264 speed preset
  int av1_preset = 12;                   // SVT-AV1 speed preset, 0 (slowest) to 13
};

// "h264" or "av1": the value of LeRobot's `video.codec` and of FFmpeg's codec name.
std::string VideoCodecName(VideoCodec codec);

// "h264" or "av1" (also "libsvtav1", LeRobot's name) -> codec; throws std::invalid_argument
// naming the value otherwise.
VideoCodec ParseVideoCodec(const std::string& name);

// The first thing wrong with the settings, naming the bad value ("width 63 is odd; ..."), or ""
// when they are usable: non-positive or odd width or height, av1 frames under 64x64 (SVT-AV1's
// minimum), non-positive fps or gop, crf or preset outside the codec's range.
std::string VideoSettingsProblem(const VideoSettings& settings);
// Throws std::invalid_argument "video PATH: PROBLEM" for such a problem.
void ValidateVideoSettings(const VideoSettings& settings, const std::string& path);

}  // namespace tavis::batch::dataset::video

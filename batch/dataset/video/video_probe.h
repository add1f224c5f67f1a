// ProbeVideo: what libavformat reads back from a video file's first video stream, the values a
// dataset's info.json declares (codec, pix_fmt, size, fps) and LeRobot's `to_timestamp`
// (the stream duration).
#pragma once

#include <cstdint>
#include <string>

namespace tavis::batch::dataset::video {

struct VideoProbe {
  std::string codec;    // FFmpeg's codec name: "h264", "av1"
  std::string pix_fmt;  // e.g. "yuv420p"
  int width = 0;
  int height = 0;
  int fps_num = 0;  // average frame rate, num / den
  int fps_den = 1;
  std::int64_t frame_count = 0;  // as the container's index states it
  double duration_s = 0;         // stream duration * time_base, as LeRobot probes it
};

// Throws std::runtime_error naming the file and FFmpeg's message when it cannot be read or has
// no video stream.
VideoProbe ProbeVideo(const std::string& path);

}  // namespace tavis::batch::dataset::video

#include "batch/dataset/video/ffmpeg_error.h"

#include <stdexcept>

extern "C" {
#include <libavutil/error.h>
}

namespace tavis::batch::dataset::video::internal {

std::string FfmpegErrorText(int code) {
  char text[AV_ERROR_MAX_STRING_SIZE] = {};
  if (av_strerror(code, text, sizeof(text)) < 0) return "FFmpeg error " + std::to_string(code);
  return text;
}

void ThrowFfmpegError(const std::string& path, const std::string& what, int code) {
  throw std::runtime_error("video " + path + ": " + what + ": " + FfmpegErrorText(code));
}

int CheckFfmpeg(int code, const std::string& path, const std::string& what) {
  if (code < 0) ThrowFfmpegError(path, what, code);
  return code;
}

}  // namespace tavis::batch::dataset::video::internal

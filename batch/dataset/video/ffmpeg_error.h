// Internal to tavis_video: FFmpeg error codes turned into exceptions that name the file.
#pragma once

#include <string>

namespace tavis::batch::dataset::video::internal {

// FFmpeg's text for an AVERROR code (av_strerror).
std::string FfmpegErrorText(int code);

// Throws std::runtime_error "video <path>: <what>: <FFmpeg's message>".
[[noreturn]] void ThrowFfmpegError(const std::string& path, const std::string& what, int code);

// Calls ThrowFfmpegError when `code` is negative; returns `code` otherwise.
int CheckFfmpeg(int code, const std::string& path, const std::string& what);

}  // namespace tavis::batch::dataset::video::internal

// Internal to tavis_video: the FFmpeg encoder of one episode and the stream parameters it hands
// the mp4 writer with its packets.
#pragma once

#include <memory>
#include <string>

extern "C" {
#include <libavcodec/avcodec.h>
}

#include "batch/dataset/video/video_settings.h"

namespace tavis::batch::dataset::video {

struct StreamParameters {
  StreamParameters() = default;
  StreamParameters(const StreamParameters&) = delete;
  StreamParameters& operator=(const StreamParameters&) = delete;
  ~StreamParameters() { avcodec_parameters_free(&codec); }

  AVCodecParameters* codec = nullptr;
  AVRational time_base{0, 1};
  AVRational frame_rate{0, 1};
};

}  // namespace tavis::batch::dataset::video

namespace tavis::batch::dataset::video::internal {

// Encoders are opened and freed one at a time across the process: SVT-AV1 1.4's
// svt_av1_enc_init_handle sets up process-wide state without a lock, and encoders opened
// concurrently on several threads crashed in it. parquet::Encoding itself runs in parallel.
struct CodecContextFree {
  void operator()(AVCodecContext* context) const;
};
using CodecContextPtr = std::unique_ptr<AVCodecContext, CodecContextFree>;

// An open encoder for `settings` with global headers (mp4 keeps them in the stream header), one
// thread, time base 1/fps. Throws std::runtime_error naming `name` and FFmpeg's message.
CodecContextPtr OpenEncoder(const VideoSettings& settings, const std::string& name);

// The stream parameters of an open encoder.
std::shared_ptr<const StreamParameters> ParametersOf(const AVCodecContext& encoder, const std::string& name);

}  // namespace tavis::batch::dataset::video::internal

#include "batch/dataset/video/video_probe.h"

#include <memory>
#include <stdexcept>

extern "C" {
#include <libavformat/avformat.h>
#include <libavutil/pixdesc.h>
}

#include "batch/dataset/video/ffmpeg_error.h"

namespace tavis::batch::dataset::video {
namespace {

struct InputClose {
  void operator()(AVFormatContext* input) const { avformat_close_input(&input); }
};

}  // namespace

VideoProbe ProbeVideo(const std::string& path) {
  AVFormatContext* raw_input = nullptr;
  internal::CheckFfmpeg(avformat_open_input(&raw_input, path.c_str(), nullptr, nullptr), path, "opening");
  const std::unique_ptr<AVFormatContext, InputClose> input(raw_input);
  internal::CheckFfmpeg(avformat_find_stream_info(input.get(), nullptr), path, "reading stream info");
  const int index = internal::CheckFfmpeg(av_find_best_stream(input.get(), AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0),
                                          path, "finding a video stream");
  const AVStream& stream = *input->streams[index];
  const AVCodecParameters& parameters = *stream.codecpar;

  VideoProbe probe;
  probe.codec = avcodec_get_name(parameters.codec_id);
  const char* pix_fmt = av_get_pix_fmt_name(static_cast<AVPixelFormat>(parameters.format));
  probe.pix_fmt = pix_fmt != nullptr ? pix_fmt : "unknown";
  probe.width = parameters.width;
  probe.height = parameters.height;
  probe.fps_num = stream.avg_frame_rate.num;
  probe.fps_den = stream.avg_frame_rate.den;
  probe.frame_count = stream.nb_frames;
  probe.duration_s = static_cast<double>(stream.duration) * av_q2d(stream.time_base);
  return probe;
}

}  // namespace tavis::batch::dataset::video

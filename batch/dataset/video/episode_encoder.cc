#include "batch/dataset/video/episode_encoder.h"

#include <mutex>
#include <stdexcept>
#include <utility>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

#include "batch/dataset/video/deterministic_heap.h"
#include "batch/dataset/video/encoder_context.h"
#include "batch/dataset/video/encoder_options.h"
#include "batch/dataset/video/ffmpeg_error.h"

namespace tavis::batch::dataset::video {
namespace internal {
namespace {

std::mutex& EncoderLifecycleMutex() {
  static std::mutex mutex;
  return mutex;
}

}  // namespace

void CodecContextFree::operator()(AVCodecContext* context) const {
  const std::lock_guard<std::mutex> lock(EncoderLifecycleMutex());
  avcodec_free_context(&context);
}

CodecContextPtr OpenEncoder(const VideoSettings& settings, const std::string& name) {
  MakeHeapContentDeterministic();  // before the encoder allocates anything (deterministic_heap.h)
  const EncoderChoice choice = ChooseEncoder(settings);
  const AVCodec* codec = avcodec_find_encoder_by_name(choice.encoder_name.c_str());
  if (codec == nullptr)
    throw std::runtime_error("video " + name + ": encoder " + choice.encoder_name +
                             " is not available in this FFmpeg build");
  CodecContextPtr context(avcodec_alloc_context3(codec));
  if (!context) throw std::runtime_error("video " + name + ": cannot allocate the " + choice.encoder_name + " encoder");
  context->width = settings.width;
  context->height = settings.height;
  context->pix_fmt = AV_PIX_FMT_YUV420P;
  context->time_base = AVRational{1, settings.fps};  // pts counts frames
  context->framerate = AVRational{settings.fps, 1};
  context->gop_size = settings.gop;
  context->max_b_frames = 0;
  context->thread_count = 1;  // determinism: libx264's frame threads would change the bytes
  // What libswscale's RGB -> YUV conversion produces: BT.601, limited range.
  context->colorspace = AVCOL_SPC_SMPTE170M;
  context->color_range = AVCOL_RANGE_MPEG;
  context->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;  // mp4 keeps the headers in the stream
  for (const auto& [option, value] : choice.private_options) {
    CheckFfmpeg(av_opt_set(context->priv_data, option.c_str(), value.c_str(), 0), name,
                "setting " + choice.encoder_name + " option " + option + "=" + value);
  }
  int opened = 0;
  {
    const std::lock_guard<std::mutex> lock(EncoderLifecycleMutex());
    opened = avcodec_open2(context.get(), codec, nullptr);
  }
  CheckFfmpeg(opened, name,
              "opening encoder " + choice.encoder_name + " for " + std::to_string(settings.width) + "x" +
                  std::to_string(settings.height));
  return context;
}

std::shared_ptr<const StreamParameters> ParametersOf(const AVCodecContext& encoder, const std::string& name) {
  auto parameters = std::make_shared<StreamParameters>();
  parameters->codec = avcodec_parameters_alloc();
  if (parameters->codec == nullptr)
    throw std::runtime_error("video " + name + ": out of memory for the stream parameters");
  CheckFfmpeg(avcodec_parameters_from_context(parameters->codec, &encoder), name, "copying codec parameters");
  parameters->time_base = encoder.time_base;
  parameters->frame_rate = encoder.framerate;
  return parameters;
}

}  // namespace internal

namespace {

struct FrameFree {
  void operator()(AVFrame* frame) const { av_frame_free(&frame); }
};
struct PacketFree {
  void operator()(AVPacket* packet) const { av_packet_free(&packet); }
};
struct ScalerFree {
  void operator()(SwsContext* scaler) const { sws_freeContext(scaler); }
};

}  // namespace

std::int64_t EncodedEpisode::bytes() const {
  std::int64_t total = 0;
  for (const EncodedPacket& packet : packets) total += static_cast<std::int64_t>(packet.data.size());
  return total;
}

struct EpisodeEncoder::Impl {
  VideoSettings settings;
  std::string name;
  internal::CodecContextPtr encoder;
  std::unique_ptr<SwsContext, ScalerFree> scaler;
  std::unique_ptr<AVFrame, FrameFree> frame;
  std::unique_ptr<AVPacket, PacketFree> packet;
  EncodedEpisode episode;
  bool finished = false;

  [[noreturn]] void Fail(const std::string& problem) const {
    throw std::runtime_error("video " + name + ": " + problem);
  }

  void Drain() {
    while (true) {
      const int received = avcodec_receive_packet(encoder.get(), packet.get());
      if (received == AVERROR(EAGAIN) || received == AVERROR_EOF) return;
      internal::CheckFfmpeg(received, name, "encoding");
      episode.packets.push_back({std::vector<std::uint8_t>(packet->data, packet->data + packet->size), packet->pts,
                                 packet->dts, (packet->flags & AV_PKT_FLAG_KEY) != 0});
      av_packet_unref(packet.get());
    }
  }
};

EpisodeEncoder::EpisodeEncoder(VideoSettings settings, std::string name) : impl_(std::make_unique<Impl>()) {
  Impl& impl = *impl_;
  impl.settings = std::move(settings);
  impl.name = std::move(name);
  ValidateVideoSettings(impl.settings, impl.name);
  impl.encoder = internal::OpenEncoder(impl.settings, impl.name);
  impl.episode.parameters = internal::ParametersOf(*impl.encoder, impl.name);
  impl.scaler.reset(sws_getContext(impl.settings.width, impl.settings.height, AV_PIX_FMT_RGB24, impl.settings.width,
                                   impl.settings.height, AV_PIX_FMT_YUV420P, SWS_BILINEAR, nullptr, nullptr, nullptr));
  if (!impl.scaler) impl.Fail("cannot create the RGB24 -> yuv420p converter");
  impl.frame.reset(av_frame_alloc());
  impl.packet.reset(av_packet_alloc());
  if (!impl.frame || !impl.packet) impl.Fail("out of memory allocating a frame");
  impl.frame->format = AV_PIX_FMT_YUV420P;
  impl.frame->width = impl.settings.width;
  impl.frame->height = impl.settings.height;
  internal::CheckFfmpeg(av_frame_get_buffer(impl.frame.get(), 0), impl.name, "allocating the yuv420p frame");
}

EpisodeEncoder::~EpisodeEncoder() = default;
EpisodeEncoder::EpisodeEncoder(EpisodeEncoder&&) noexcept = default;
EpisodeEncoder& EpisodeEncoder::operator=(EpisodeEncoder&&) noexcept = default;

void EpisodeEncoder::WriteFrame(const std::uint8_t* rgb, std::size_t rgb_size) {
  Impl& impl = *impl_;
  if (impl.finished) impl.Fail("WriteFrame after Finish");
  const std::size_t expected =
      static_cast<std::size_t>(impl.settings.width) * static_cast<std::size_t>(impl.settings.height) * 3;
  if (rgb_size != expected) {
    impl.Fail("frame of " + std::to_string(rgb_size) + " bytes, expected " + std::to_string(impl.settings.width) + "x" +
              std::to_string(impl.settings.height) + "x3 = " + std::to_string(expected));
  }
  internal::CheckFfmpeg(av_frame_make_writable(impl.frame.get()), impl.name, "preparing the frame");
  const std::uint8_t* const source[1] = {rgb};
  const int source_stride[1] = {impl.settings.width * 3};
  sws_scale(impl.scaler.get(), source, source_stride, 0, impl.settings.height, impl.frame->data, impl.frame->linesize);
  impl.frame->pts = impl.episode.frames;
  internal::CheckFfmpeg(avcodec_send_frame(impl.encoder.get(), impl.frame.get()), impl.name,
                        "encoding frame " + std::to_string(impl.episode.frames));
  ++impl.episode.frames;
  impl.Drain();
}

EncodedEpisode EpisodeEncoder::Finish() {
  Impl& impl = *impl_;
  if (impl.finished) impl.Fail("Finish called twice");
  internal::CheckFfmpeg(avcodec_send_frame(impl.encoder.get(), nullptr), impl.name, "flushing the encoder");
  impl.Drain();
  impl.finished = true;
  impl.encoder.reset();
  return std::move(impl.episode);
}

std::int64_t EpisodeEncoder::frames() const { return impl_->episode.frames; }
std::int64_t EpisodeEncoder::bytes() const { return impl_->episode.bytes(); }
const VideoSettings& EpisodeEncoder::settings() const { return impl_->settings; }

}  // namespace tavis::batch::dataset::video

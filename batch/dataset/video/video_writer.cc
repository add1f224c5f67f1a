#include "batch/dataset/video/video_writer.h"

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <utility>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

#include "batch/dataset/video/encoder_options.h"
#include "batch/dataset/video/ffmpeg_error.h"

namespace tavis::dataset {
namespace {

using internal::CheckFfmpeg;

// Encoders are opened and freed one at a time across the process: SVT-AV1 1.4's
// svt_av1_enc_init_handle sets up process-wide state without a lock, and writers opened
// concurrently on several threads crashed in it. Encoding itself runs in parallel.
std::mutex& EncoderLifecycleMutex() {
  static std::mutex mutex;
  return mutex;
}

struct CodecContextFree {
  void operator()(AVCodecContext* context) const {
    const std::lock_guard<std::mutex> lock(EncoderLifecycleMutex());
    avcodec_free_context(&context);
  }
};
struct FrameFree {
  void operator()(AVFrame* frame) const { av_frame_free(&frame); }
};
struct PacketFree {
  void operator()(AVPacket* packet) const { av_packet_free(&packet); }
};
struct ScalerFree {
  void operator()(SwsContext* scaler) const { sws_freeContext(scaler); }
};
// The output file: closes the file (if opened) before freeing the muxer.
struct MuxerFree {
  void operator()(AVFormatContext* muxer) const {
    if (muxer->pb != nullptr) avio_closep(&muxer->pb);
    avformat_free_context(muxer);
  }
};

using CodecContextPtr = std::unique_ptr<AVCodecContext, CodecContextFree>;

}  // namespace

struct Mp4VideoWriter::Impl {
  std::string path;
  std::string partial_path;
  VideoSettings settings;
  std::unique_ptr<AVFormatContext, MuxerFree> muxer;
  AVStream* stream = nullptr;  // owned by muxer
  CodecContextPtr encoder;
  std::unique_ptr<SwsContext, ScalerFree> scaler;
  std::unique_ptr<AVFrame, FrameFree> frame;
  std::unique_ptr<AVPacket, PacketFree> packet;
  std::int64_t frames = 0;
  std::int64_t final_size = -1;  // the file's size once closed
  bool episode_pending = false;  // BeginEpisode() called, its first frame not yet written
  bool closed = false;

  Impl(std::string file, VideoSettings video) : path(std::move(file)), partial_path(path + ".partial"), settings(std::move(video)) {}

  ~Impl() {
    if (closed) return;
    muxer.reset();  // closes the partial file before it is removed
    std::remove(partial_path.c_str());
  }

  [[noreturn]] void Fail(const std::string& problem) const { throw std::runtime_error("video " + path + ": " + problem); }

  // A fresh encoder. Every episode gets one, as LeRobot encodes each episode into its own
  // file: its first frame is then a keyframe for any codec (SVT-AV1 1.4 ignores forced
  // keyframes) and no episode's encoding depends on the one before.
  CodecContextPtr OpenEncoder() const {
    const internal::EncoderChoice choice = internal::ChooseEncoder(settings);
    const AVCodec* codec = avcodec_find_encoder_by_name(choice.encoder_name.c_str());
    if (codec == nullptr) Fail("encoder " + choice.encoder_name + " is not available in this FFmpeg build");
    CodecContextPtr context(avcodec_alloc_context3(codec));
    if (!context) Fail("cannot allocate the " + choice.encoder_name + " encoder");
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
    if ((muxer->oformat->flags & AVFMT_GLOBALHEADER) != 0) context->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
    for (const auto& [name, value] : choice.private_options) {
      CheckFfmpeg(av_opt_set(context->priv_data, name.c_str(), value.c_str(), 0), path,
                  "setting " + choice.encoder_name + " option " + name + "=" + value);
    }
    int opened = 0;
    {
      const std::lock_guard<std::mutex> lock(EncoderLifecycleMutex());
      opened = avcodec_open2(context.get(), codec, nullptr);
    }
    CheckFfmpeg(opened, path,
                "opening encoder " + choice.encoder_name + " for " + std::to_string(settings.width) + "x" +
                    std::to_string(settings.height));
    return context;
  }

  void Open() {
    ValidateVideoSettings(settings, path);
    AVFormatContext* raw_muxer = nullptr;
    // The muxer is named: the ".partial" suffix would not select mp4.
    CheckFfmpeg(avformat_alloc_output_context2(&raw_muxer, nullptr, "mp4", partial_path.c_str()), path,
                "creating the mp4 muxer");
    muxer.reset(raw_muxer);
    stream = avformat_new_stream(muxer.get(), nullptr);
    if (stream == nullptr) Fail("cannot add a video stream");
    encoder = OpenEncoder();
    CheckFfmpeg(avcodec_parameters_from_context(stream->codecpar, encoder.get()), path, "copying codec parameters");
    stream->time_base = encoder->time_base;
    stream->avg_frame_rate = encoder->framerate;
    CheckFfmpeg(avio_open(&muxer->pb, partial_path.c_str(), AVIO_FLAG_WRITE), path,
                "opening " + partial_path + " for writing");
    AVDictionary* options = nullptr;
    av_dict_set(&options, "movflags", "+faststart", 0);
    const int header = avformat_write_header(muxer.get(), &options);
    av_dict_free(&options);
    CheckFfmpeg(header, path, "writing the mp4 header");

    scaler.reset(sws_getContext(settings.width, settings.height, AV_PIX_FMT_RGB24, settings.width, settings.height,
                                AV_PIX_FMT_YUV420P, SWS_BILINEAR, nullptr, nullptr, nullptr));
    if (!scaler) Fail("cannot create the RGB24 -> yuv420p converter");
    frame.reset(av_frame_alloc());
    packet.reset(av_packet_alloc());
    if (!frame || !packet) Fail("out of memory allocating a frame");
    frame->format = AV_PIX_FMT_YUV420P;
    frame->width = settings.width;
    frame->height = settings.height;
    CheckFfmpeg(av_frame_get_buffer(frame.get(), 0), path, "allocating the yuv420p frame");
  }

  // Muxes every packet the encoder has ready; each lasts one frame, the last included, so the
  // stream's duration is exactly frames / fps.
  void DrainPackets() {
    while (true) {
      const int received = avcodec_receive_packet(encoder.get(), packet.get());
      if (received == AVERROR(EAGAIN) || received == AVERROR_EOF) return;
      CheckFfmpeg(received, path, "encoding");
      packet->duration = 1;
      av_packet_rescale_ts(packet.get(), encoder->time_base, stream->time_base);
      packet->stream_index = stream->index;
      CheckFfmpeg(av_interleaved_write_frame(muxer.get(), packet.get()), path,
                  "writing frame data to " + partial_path);
    }
  }

  void FlushEncoder() {
    CheckFfmpeg(avcodec_send_frame(encoder.get(), nullptr), path, "flushing the encoder");
    DrainPackets();
  }

  // Replaces the encoder; the new one must describe the stream exactly as the first did, since
  // the mp4 holds one set of codec parameters.
  void RestartEncoder() {
    FlushEncoder();
    CodecContextPtr next = OpenEncoder();
    const bool same_header = next->extradata_size == stream->codecpar->extradata_size &&
                             std::memcmp(next->extradata, stream->codecpar->extradata,
                                         static_cast<std::size_t>(next->extradata_size)) == 0;
    if (!same_header) Fail("the restarted encoder's stream header differs from the first one's");
    encoder = std::move(next);
  }
};

Mp4VideoWriter::Mp4VideoWriter(std::string path, VideoSettings settings)
    : impl_(std::make_unique<Impl>(std::move(path), std::move(settings))) {
  impl_->Open();
}

Mp4VideoWriter::~Mp4VideoWriter() = default;
Mp4VideoWriter::Mp4VideoWriter(Mp4VideoWriter&&) noexcept = default;
Mp4VideoWriter& Mp4VideoWriter::operator=(Mp4VideoWriter&&) noexcept = default;

void Mp4VideoWriter::BeginEpisode() {
  if (impl_->closed) impl_->Fail("BeginEpisode after Close");
  impl_->episode_pending = true;
}

void Mp4VideoWriter::WriteFrame(const std::uint8_t* rgb, std::size_t rgb_size) {
  Impl& writer = *impl_;
  if (writer.closed) writer.Fail("WriteFrame after Close");
  const std::size_t expected = static_cast<std::size_t>(writer.settings.width) *
                               static_cast<std::size_t>(writer.settings.height) * 3;
  if (rgb_size != expected) {
    writer.Fail("frame of " + std::to_string(rgb_size) + " bytes, expected " + std::to_string(writer.settings.width) +
                "x" + std::to_string(writer.settings.height) + "x3 = " + std::to_string(expected));
  }
  if (writer.episode_pending && writer.frames > 0) writer.RestartEncoder();
  writer.episode_pending = false;

  CheckFfmpeg(av_frame_make_writable(writer.frame.get()), writer.path, "preparing the frame");
  const std::uint8_t* const source[1] = {rgb};
  const int source_stride[1] = {writer.settings.width * 3};
  sws_scale(writer.scaler.get(), source, source_stride, 0, writer.settings.height, writer.frame->data,
            writer.frame->linesize);
  writer.frame->pts = writer.frames;
  CheckFfmpeg(avcodec_send_frame(writer.encoder.get(), writer.frame.get()), writer.path,
              "encoding frame " + std::to_string(writer.frames));
  ++writer.frames;
  writer.DrainPackets();
}

void Mp4VideoWriter::Close() {
  Impl& writer = *impl_;
  if (writer.closed) return;
  writer.FlushEncoder();
  CheckFfmpeg(av_write_trailer(writer.muxer.get()), writer.path, "writing the mp4 index");
  CheckFfmpeg(avio_closep(&writer.muxer->pb), writer.path, "closing " + writer.partial_path);
  std::error_code error;
  std::filesystem::rename(writer.partial_path, writer.path, error);
  if (error) writer.Fail("renaming " + writer.partial_path + ": " + error.message());
  writer.closed = true;
  const std::uintmax_t size = std::filesystem::file_size(writer.path, error);
  writer.final_size = error ? -1 : static_cast<std::int64_t>(size);
  writer.muxer.reset();
  writer.encoder.reset();
}

std::int64_t Mp4VideoWriter::frames_written() const { return impl_->frames; }

std::int64_t Mp4VideoWriter::bytes_written() const {
  if (impl_->closed) return impl_->final_size;
  return avio_tell(impl_->muxer->pb);
}

const std::string& Mp4VideoWriter::path() const { return impl_->path; }
const VideoSettings& Mp4VideoWriter::settings() const { return impl_->settings; }

}  // namespace tavis::dataset

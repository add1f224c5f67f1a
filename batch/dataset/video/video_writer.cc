#include "batch/dataset/video/video_writer.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <utility>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
}

#include "batch/dataset/video/encoder_context.h"
#include "batch/dataset/video/ffmpeg_error.h"

namespace tavis::batch::dataset::video {
namespace {

using internal::CheckFfmpeg;

struct PacketFree {
  void operator()(AVPacket* packet) const { av_packet_free(&packet); }
};
// The output file: closes the file (if opened) before freeing the muxer.
struct MuxerFree {
  void operator()(AVFormatContext* muxer) const {
    if (muxer->pb != nullptr) avio_closep(&muxer->pb);
    avformat_free_context(muxer);
  }
};

}  // namespace

struct Mp4VideoWriter::Impl {
  std::string path;
  std::string partial_path;
  VideoSettings settings;
  std::unique_ptr<AVFormatContext, MuxerFree> muxer;
  AVStream* stream = nullptr;  // owned by muxer
  std::unique_ptr<AVPacket, PacketFree> packet;
  std::optional<EpisodeEncoder> current;  // the episode WriteFrame is encoding
  std::int64_t frames = 0;                // appended to the file
  std::int64_t final_size = -1;           // the file's size once closed
  bool header_written = false;            // at the first episode
  bool closed = false;

  Impl(std::string file, VideoSettings video)
      : path(std::move(file)), partial_path(path + ".partial"), settings(std::move(video)) {}

  ~Impl() {
    if (closed) return;
    muxer.reset();  // closes the partial file before it is removed
    std::remove(partial_path.c_str());
  }

  [[noreturn]] void Fail(const std::string& problem) const {
    throw std::runtime_error("video " + path + ": " + problem);
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
    CheckFfmpeg(avio_open(&muxer->pb, partial_path.c_str(), AVIO_FLAG_WRITE), path,
                "opening " + partial_path + " for writing");
    packet.reset(av_packet_alloc());
    if (!packet) Fail("out of memory allocating a packet");
  }

  // The mp4 header, from the first episode's stream parameters (an encoder opened only to describe
  // the stream and closed without a frame hangs SVT-AV1 1.4).
  void WriteHeader(const StreamParameters& parameters) {
    CheckFfmpeg(avcodec_parameters_copy(stream->codecpar, parameters.codec), path, "copying codec parameters");
    stream->time_base = parameters.time_base;
    stream->avg_frame_rate = parameters.frame_rate;
    AVDictionary* options = nullptr;
    av_dict_set(&options, "movflags", "+faststart", 0);
    const int header = avformat_write_header(muxer.get(), &options);
    av_dict_free(&options);
    CheckFfmpeg(header, path, "writing the mp4 header");
    header_written = true;
  }

  // Muxes the episode's packets after the file's frames; each lasts one frame, the last included,
  // so the stream's duration is exactly frames / fps.
  void Append(const EncodedEpisode& episode) {
    if (!episode.parameters) throw std::invalid_argument("video " + path + ": the episode has no stream parameters");
    const AVCodecParameters& incoming = *episode.parameters->codec;
    if (incoming.width != settings.width || incoming.height != settings.height) {
      throw std::invalid_argument("video " + path + ": an episode of " + std::to_string(incoming.width) + "x" +
                                  std::to_string(incoming.height) + " frames in a " + std::to_string(settings.width) +
                                  "x" + std::to_string(settings.height) + " file");
    }
    if (!header_written) WriteHeader(*episode.parameters);
    const AVCodecParameters& parameters = *stream->codecpar;
    const bool same_header =
        parameters.codec_id == incoming.codec_id && parameters.extradata_size == incoming.extradata_size &&
        std::equal(incoming.extradata, incoming.extradata + incoming.extradata_size, parameters.extradata);
    if (!same_header) {
      throw std::invalid_argument(
          "video " + path + ": the episode's stream header differs from the file's (encoded with other settings)");
    }
    const AVRational frame_base{1, settings.fps};
    for (const EncodedPacket& encoded : episode.packets) {
      CheckFfmpeg(av_new_packet(packet.get(), static_cast<int>(encoded.data.size())), path, "allocating a packet");
      std::copy(encoded.data.begin(), encoded.data.end(), packet->data);
      packet->pts = encoded.pts + frames;
      packet->dts = encoded.dts + frames;
      packet->duration = 1;
      if (encoded.key) packet->flags |= AV_PKT_FLAG_KEY;
      av_packet_rescale_ts(packet.get(), frame_base, stream->time_base);
      packet->stream_index = stream->index;
      CheckFfmpeg(av_interleaved_write_frame(muxer.get(), packet.get()), path, "writing frame data to " + partial_path);
    }
    frames += episode.frames;
  }

  void AppendCurrent() {
    if (current && current->frames() > 0) Append(current->Finish());
    current.reset();
  }
};

Mp4VideoWriter::Mp4VideoWriter(std::string path, VideoSettings settings)
    : impl_(std::make_unique<Impl>(std::move(path), std::move(settings))) {
  impl_->Open();
}

Mp4VideoWriter::~Mp4VideoWriter() = default;
Mp4VideoWriter::Mp4VideoWriter(Mp4VideoWriter&&) noexcept = default;
Mp4VideoWriter& Mp4VideoWriter::operator=(Mp4VideoWriter&&) noexcept = default;

void Mp4VideoWriter::AppendEpisode(const EncodedEpisode& episode) {
  if (impl_->closed) impl_->Fail("AppendEpisode after Close");
  impl_->AppendCurrent();
  impl_->Append(episode);
}

void Mp4VideoWriter::BeginEpisode() {
  if (impl_->closed) impl_->Fail("BeginEpisode after Close");
  impl_->AppendCurrent();
}

void Mp4VideoWriter::WriteFrame(const std::uint8_t* rgb, std::size_t rgb_size) {
  Impl& writer = *impl_;
  if (writer.closed) writer.Fail("WriteFrame after Close");
  if (!writer.current) writer.current.emplace(writer.settings, writer.path);
  writer.current->WriteFrame(rgb, rgb_size);
}

void Mp4VideoWriter::Close() {
  Impl& writer = *impl_;
  if (writer.closed) return;
  writer.AppendCurrent();
  if (!writer.header_written) writer.Fail("no frame to write: an mp4 needs at least one");
  CheckFfmpeg(av_write_trailer(writer.muxer.get()), writer.path, "writing the mp4 index");
  CheckFfmpeg(avio_closep(&writer.muxer->pb), writer.path, "closing " + writer.partial_path);
  std::error_code error;
  std::filesystem::rename(writer.partial_path, writer.path, error);
  if (error) writer.Fail("renaming " + writer.partial_path + ": " + error.message());
  writer.closed = true;
  const std::uintmax_t size = std::filesystem::file_size(writer.path, error);
  writer.final_size = error ? -1 : static_cast<std::int64_t>(size);
  writer.muxer.reset();
}

std::int64_t Mp4VideoWriter::frames_written() const {
  return impl_->frames + (impl_->current ? impl_->current->frames() : 0);
}

std::int64_t Mp4VideoWriter::bytes_written() const {
  if (impl_->closed) return impl_->final_size;
  return avio_tell(impl_->muxer->pb) + (impl_->current ? impl_->current->bytes() : 0);
}

const std::string& Mp4VideoWriter::path() const { return impl_->path; }
const VideoSettings& Mp4VideoWriter::settings() const { return impl_->settings; }

}  // namespace tavis::batch::dataset::video
